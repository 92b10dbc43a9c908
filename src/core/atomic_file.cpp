#include "deepsea/core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

void require_writable_folder(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::exists(dir, ec)) throw IoError(path + ": folder " + dir.string() + " does not exist");
    if (!fs::is_directory(dir, ec)) throw IoError(path + ": " + dir.string() + " is not a folder");
    if (::access(dir.c_str(), W_OK) != 0) {
        throw IoError(path + ": cannot write into " + dir.string() + ": " + std::strerror(errno));
    }
}

namespace {

constexpr const char* kTmpTag = ".tmp-";

/// The temporary for `target`: hidden, unique per process and call, and keeps the extension
/// for format-by-name writers. parse_temporary_name reads it back.
fs::path temporary_for(const fs::path& target, unsigned serial) {
    return target.parent_path() /
           ("." + target.stem().string() + kTmpTag + std::to_string(::getpid()) + "-" +
            std::to_string(serial) + target.extension().string());
}

bool all_digits(const std::string& s) {
    return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

std::optional<TemporaryName> parse_temporary_name(const std::string& file_name) {
    // .<stem>.tmp-<pid>-<serial><extension>; the stem may itself hold ".tmp-".
    if (file_name.size() < 2 || file_name[0] != '.') return std::nullopt;
    const std::size_t tag = file_name.rfind(kTmpTag);
    if (tag == std::string::npos || tag < 1) return std::nullopt;
    const std::string rest = file_name.substr(tag + std::strlen(kTmpTag));
    const std::size_t dash = rest.find('-');
    if (dash == std::string::npos) return std::nullopt;
    const std::string pid = rest.substr(0, dash);
    std::string serial = rest.substr(dash + 1), ext;
    const std::size_t dot = serial.find('.');
    if (dot != std::string::npos) {
        ext = serial.substr(dot);
        serial.resize(dot);
    }
    if (!all_digits(pid) || !all_digits(serial) || pid.size() > 9) return std::nullopt;
    return TemporaryName{file_name.substr(1, tag - 1) + ext, std::stol(pid)};
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& tmp)>& write) {
    require_writable_folder(path);
    static std::atomic<unsigned> serial{0};
    const fs::path target(path);
    const fs::path tmp = temporary_for(target, serial++);
    const auto cleanup = [&] {
        std::error_code rm;
        fs::remove(tmp, rm);
    };
    try {
        write(tmp.string());
    } catch (...) {
        cleanup();
        throw;
    }
    std::error_code ec;
    // A full disk can leave a short file that the writer did not report.
    if (!fs::exists(tmp, ec) || fs::file_size(tmp, ec) == 0 || ec) {
        cleanup();
        throw IoError(path + ": write failed: the file is empty (disk full?)");
    }
    fs::rename(tmp, target, ec);
    if (ec) {
        cleanup();
        throw IoError(path + ": cannot rename the temporary file: " + ec.message());
    }
}

void write_text_atomically(const std::string& path, const std::string& text) {
    write_atomically(path, [&](const std::string& tmp) { write_fully(tmp, text, path); });
}

void write_fully(const std::string& file, std::string_view bytes, const std::string& name) {
    const auto fail = [&](const char* what) {
        throw IoError(name + ": " + what + ": " + std::strerror(errno));
    };
    const int fd = ::open(file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) fail("cannot create");
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = ENOSPC;  // no progress: the device took nothing
            const int err = errno;
            ::close(fd);
            errno = err;
            fail("write failed");
        }
        done += std::size_t(n);
    }
    // Delayed allocation (and network file systems) can report a full disk only here.
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        const int err = errno;
        ::close(fd);
        errno = err;
        fail("write failed");
    }
    if (::close(fd) != 0) fail("write failed");
}

void require_distinct(const std::string& output,
                      const std::vector<std::pair<std::string, std::string>>& others) {
    std::error_code ec;
    const bool exists = fs::exists(output, ec);
    const fs::path canonical = fs::weakly_canonical(output, ec);
    for (const auto& [other, what] : others) {
        if (other.empty()) continue;
        std::error_code e2;
        // An existing file: the same inode, through links and relative paths alike; two files
        // still to be written: the same place.
        const bool same = exists ? fs::equivalent(output, other, e2)
                                 : !ec && fs::weakly_canonical(other, e2) == canonical && !e2;
        if (same) {
            throw IoError(output + ": is the same file as " + what + " " + other +
                          " (choose another output)");
        }
    }
}

}  // namespace deepsea
