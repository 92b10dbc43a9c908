#pragma once
// Config text with one piece swapped, for the tests that feed a valid config with one bad
// value: the first `from` in `text` replaced by `to` (a test failure if `from` is not there).

#include <gtest/gtest.h>

#include <string>

namespace deepsea::test {

inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    const auto p = text.find(from);
    EXPECT_NE(p, std::string::npos) << from;
    return p == std::string::npos ? text : text.replace(p, from.size(), to);
}

}  // namespace deepsea::test
