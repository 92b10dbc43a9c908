#include "deepsea/core/input_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

std::string megabytes(std::uintmax_t bytes) {
    return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB";
}

}  // namespace

void require_input_file(const std::string& path, std::uintmax_t max_bytes,
                        const std::string& what) {
    if (path.empty()) throw IoError("an empty file name was given for " + what);
    if (path.find('\0') != std::string::npos)
        throw IoError(path.substr(0, path.find('\0')) + "...: the file name holds a NUL character");
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec && ec != std::errc::no_such_file_or_directory) throw IoError(path + ": " + ec.message());
    if (!fs::exists(st)) throw IoError(path + ": no such file");
    if (fs::is_directory(st)) throw IoError(path + ": is a folder, not " + what);
    if (!fs::is_regular_file(st)) {
        throw IoError(path + ": is not a regular file (a device, pipe or socket); deepsea reads " +
                      what + " only from a file");
    }
    const std::uintmax_t bytes = fs::file_size(path, ec);
    if (ec) throw IoError(path + ": " + ec.message());
    if (bytes > max_bytes) {
        throw IoError(path + ": " + megabytes(bytes) + ", larger than deepsea reads for " + what +
                      " (at most " + megabytes(max_bytes) + ")");
    }
    if (::access(path.c_str(), R_OK) != 0)
        throw IoError(path + ": cannot read: " + std::strerror(errno));
}

std::string read_text_file(const std::string& path, const std::string& what,
                           std::uintmax_t max_bytes) {
    require_input_file(path, max_bytes, what);
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw IoError(path + ": cannot read: " + std::strerror(errno));
    std::string text;
    char buf[1 << 16];
    for (;;) {
        const ssize_t n = ::read(fd, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            const int e = errno;
            ::close(fd);
            throw IoError(path + ": read error: " + std::strerror(e));
        }
        if (n == 0) break;
        text.append(buf, std::size_t(n));
        if (text.size() > max_bytes) {
            ::close(fd);
            throw IoError(path + ": grew past " + megabytes(max_bytes) + " while it was read");
        }
    }
    ::close(fd);
    return text;
}

}  // namespace deepsea
