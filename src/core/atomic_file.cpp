#include "deepsea/core/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "deepsea/core/error.h"
#include "deepsea/core/hash.h"

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

/// The longest file name Linux file systems take (NAME_MAX).
constexpr std::size_t kNameMax = 255;
/// What a temporary adds to its target's stem: ".", ".tmp-", a pid (at most 7 digits on Linux)
/// and "-" and a serial of at most 10 digits.
constexpr std::size_t kTmpOverhead = 1 + 5 + 7 + 1 + 10;

/// The stem a temporary carries: the target's, or, where that would make the temporary's name
/// longer than a file name may be, its start and a hash of the whole (FNV-1a, the same in every
/// build), so that a legal 250-character output still gets a temporary.
std::string temporary_stem(const std::string& stem, const std::string& ext) {
    const std::size_t budget =
        kNameMax > kTmpOverhead + ext.size() + 24 ? kNameMax - kTmpOverhead - ext.size() : 24;
    if (stem.size() <= budget) return stem;
    const std::uint64_t h = fnv1a64(stem);
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
    return stem.substr(0, budget - 17) + "~" + hex;
}

/// The temporary for `target`: hidden, unique per process and call, and keeps the extension
/// for format-by-name writers. parse_temporary_name reads it back.
fs::path temporary_for(const fs::path& target, unsigned serial) {
    const std::string ext = target.extension().string();
    return target.parent_path() / ("." + temporary_stem(target.stem().string(), ext) + kTmpTag +
                                   std::to_string(::getpid()) + "-" + std::to_string(serial) + ext);
}

/// Where a write to `path` lands: `path` itself, or the regular file a symbolic link at `path`
/// leads to (so that a link to a shared config is written through, not replaced). IoError for
/// a link to anything but a regular file (/dev/stdout, a folder, a link that leads nowhere) and
/// for an existing path that is not a regular file (a device, a pipe): renaming over those
/// would replace them with a file.
fs::path write_target(const std::string& path) {
    if (path.empty()) throw IoError("an empty file name was given for an output");
    if (path.find('\0') != std::string::npos)
        throw IoError(path.substr(0, path.find('\0')) + "...: the file name holds a NUL character");
    std::error_code ec;
    const fs::file_status own = fs::symlink_status(path, ec);
    if (ec || !fs::exists(own)) return path;
    if (fs::is_symlink(own)) {
        const fs::path target = fs::canonical(path, ec);
        if (ec) throw IoError(path + ": is a symbolic link that leads nowhere; not written");
        if (!fs::is_regular_file(target, ec)) {
            throw IoError(path + ": is a symbolic link to " + target.string() +
                          ", which is not a regular file; deepsea writes only files");
        }
        return target;
    }
    if (!fs::is_regular_file(own)) {
        throw IoError(
            path + ": exists and is not a regular file (" +
            (fs::is_directory(own) ? std::string("a folder") : "a device, pipe or socket") +
            "); deepsea writes only files");
    }
    return path;
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

std::string temporary_key(const std::string& file_name) {
    const fs::path p(file_name);
    const std::string ext = p.extension().string();
    return temporary_stem(p.stem().string(), ext) + ext;
}

fs::path resolved_path(const std::string& path) {
    std::error_code ec;
    fs::path p = fs::absolute(path, ec).lexically_normal();
    // weakly_canonical follows links only up to the first missing component and applies the
    // rest lexically: "x/nosuch/../link" comes back as "x/link" with the link unresolved. Once
    // the missing folders are made, the kernel goes on through that link, so again until
    // nothing changes (bounded: a loop of links ends it).
    for (int i = 0; i < 40; ++i) {
        fs::path q = fs::weakly_canonical(p, ec);
        if (ec) break;
        q = q.lexically_normal();
        if (q == p) break;
        p = std::move(q);
    }
    // "in/x/.." resolves to "in/": the same folder as "in".
    if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
    return p;
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& tmp)>& write) {
    const fs::path target = write_target(path);
    require_writable_folder(target.string());
    static std::atomic<unsigned> serial{0};
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
    for (const auto& [other, what] : others) {
        if (!other.empty() && same_file(output, other)) {
            throw IoError(output + ": is the same file as " + what + " " + other +
                          " (choose another output)");
        }
    }
}

bool same_file(const std::string& a, const std::string& b) {
    std::error_code ea, eb;
    // Existing files: the same inode, through links and relative paths alike.
    if (fs::exists(a, ea) && fs::exists(b, eb)) return fs::equivalent(a, b, ea) && !ea;
    return resolved_path(a) == resolved_path(b);
}

}  // namespace deepsea
