#include "deepsea/core/atomic_file.h"

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

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& tmp)>& write) {
    require_writable_folder(path);
    static std::atomic<unsigned> serial{0};
    const fs::path target(path);
    // Hidden, unique per process and call, and keeps the extension for format-by-name writers.
    const fs::path tmp = target.parent_path() /
                         ("." + target.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                          "-" + std::to_string(serial++) + target.extension().string());
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
    write_atomically(path, [&](const std::string& tmp) {
        std::ofstream f(tmp, std::ios::binary);
        f << text;
        f.close();
        if (!f) throw IoError("cannot write " + path);
    });
}

}  // namespace deepsea
