#pragma once
// What the libFuzzer targets share: a private scratch folder on tmpfs where possible (the
// readers under test take paths).

#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace deepsea::fuzz {

/// A folder of this process's own, removed at exit: in /dev/shm when it exists (every input is
/// a file write and a read), else in TMPDIR.
inline const std::string& scratch() {
    static const std::string dir = [] {
        namespace fs = std::filesystem;
        std::string base = fs::is_directory("/dev/shm") ? "/dev/shm" : fs::temp_directory_path();
        std::string templ = base + "/deepsea-fuzz-XXXXXX";
        if (!::mkdtemp(templ.data())) {
            std::perror("mkdtemp");
            std::abort();
        }
        static const std::string keep = templ;
        std::atexit([] {
            std::error_code ec;
            std::filesystem::remove_all(keep, ec);
        });
        return templ;
    }();
    return dir;
}

/// Writes the input to scratch()/name and returns the path.
inline std::string write_input(const std::string& name, const std::uint8_t* data,
                               std::size_t size) {
    const std::string path = scratch() + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    out.close();
    if (!out) {
        std::perror(path.c_str());
        std::abort();
    }
    return path;
}

}  // namespace deepsea::fuzz
