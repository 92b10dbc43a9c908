#include "deepsea/core/error.h"

#include <gtest/gtest.h>

#include <string>

namespace deepsea {

TEST(OneLine, JoinsLinesAndBlanks) {
    EXPECT_EQ(one_line("could not open\n  file.png:\r\n\tno such file  "),
              "could not open file.png: no such file");
    EXPECT_EQ(one_line(""), "");
    EXPECT_EQ(one_line(" \n "), "");
}

TEST(OneLine, CutsHugeMessages) {
    const std::string huge(1 << 20, 'x');  // a damaged file's "name"
    const std::string s = one_line(huge, 100);
    EXPECT_EQ(s, std::string(100, 'x') + "...");
    EXPECT_EQ(one_line(huge).size(), 240u + 3u);
}

}  // namespace deepsea
