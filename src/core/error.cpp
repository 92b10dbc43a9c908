#include "deepsea/core/error.h"

#include <algorithm>
#include <charconv>

#include "deepsea/core/parallel.h"

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

std::string short_number(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

void throw_error(int exit_code, const std::string& message) {
    switch (exit_code) {
        case 2:
            throw ConfigError(message);
        case 3:
            throw InputError(message);
        case 4:
            throw IoError(message);
        case 5:
            throw AssetError(message);
        case 6:
            throw FramesFailed(message);
        case 7:
            throw AccuracyError(message);
        case 8:
            throw OutOfMemory(message);
        case 130:
            throw Cancelled(message);
        default:
            throw Error(message);
    }
}

}  // namespace deepsea
