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

namespace deepsea {

TEST(Error, ThrowErrorGivesBackTheKindOfEachExitCode) {
    for (const int code : {1, 2, 3, 4, 5, 6, 7, 8, 130, 99}) {
        try {
            throw_error(code, "frame.png: why");
        } catch (const Error& e) {
            EXPECT_EQ(e.exit_code(), code == 99 ? 1 : code);
            EXPECT_STREQ(e.what(), "frame.png: why");
        }
    }
    EXPECT_THROW(throw_error(4, "x"), IoError);
    EXPECT_THROW(throw_error(8, "x"), OutOfMemory);
}

}  // namespace deepsea
