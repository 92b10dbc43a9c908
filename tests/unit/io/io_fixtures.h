#pragma once
// What the io tests share: a fresh folder per test, and files written byte by byte.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace deepsea::test {

namespace fs = std::filesystem;

/// A fresh folder per test, removed afterwards.
class TempFolderTest : public ::testing::Test {
protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("deepsea-io-" + std::to_string(::getpid()) + "-" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
        fs::remove_all(dir_, ec);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    /// Names in the folder, to prove no temporary file is left behind.
    std::vector<std::string> listing() const {
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir_)) names.push_back(e.path().filename());
        return names;
    }
    fs::path dir_;
};

inline void write_bytes(const std::string& p, const std::string& bytes) {
    std::ofstream os(p, std::ios::binary);
    os.write(bytes.data(), std::streamsize(bytes.size()));
}

template <typename T>
std::string raw(const std::vector<T>& v) {
    // The test machine is little-endian (x86-64/aarch64), as are .npy '<' and PFM scale < 0.
    return std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

inline std::string be32(std::uint32_t v) {
    return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

}  // namespace deepsea::test
