#include "deepsea/core/error.h"

#include <algorithm>

namespace deepsea {

std::string one_line(const std::string& text, std::size_t max_chars) {
    std::string out;
    out.reserve(std::min(text.size(), max_chars + 3));
    bool blank = false;
    for (const char ch : text) {
        const unsigned char c = static_cast<unsigned char>(ch);
        if (c < 0x20 || c == 0x7f || c == ' ') {
            blank = !out.empty();
            continue;
        }
        if (blank) out += ' ';
        blank = false;
        if (out.size() >= max_chars) {
            out += "...";
            break;
        }
        out += ch;
    }
    return out;
}

}  // namespace deepsea
