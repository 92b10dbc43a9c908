#pragma once
// The message of the exception a call throws, for the tests of every layer that check what an
// error says.

#include <string>

namespace deepsea::test {

/// what() of the E that f() throws, or "" if it throws none.
template <class E, class F>
std::string message_of(F f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    return "";
}

}  // namespace deepsea::test
