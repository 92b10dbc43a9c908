// libFuzzer target: the output checks of a render (frame_jobs) against a real folder tree. The
// input's bytes pick path components ("..", ".", missing folders, links to folders and to
// frames, the input folder, an output folder) for -o and --layers, as a sequence's folders or
// one frame's files. Whatever frame_jobs accepts is then made as a render makes it (the output
// folders created, each output's write target resolved through links as write_atomically
// does), and no output may land on an input: not the same resolved path, not the same inode.
// frame_jobs must create nothing itself; anything but deepsea::Error escaping is a bug.

#include <sys/stat.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "fuzz_util.h"

namespace fs = std::filesystem;

namespace {

const char* const kParts[] = {"in",
                              "out",
                              "..",
                              ".",
                              "nosuch",
                              "a",
                              "link-in",
                              "link-out",
                              "link-frame",
                              "frame_0001.png",
                              "frame_0002.png",
                              "x.png",
                              "frame_0001.exr",
                              "hard.png",
                              "",
                              "in/",
                              "out/",
                              "dangling"};
constexpr int kPartCount = int(sizeof kParts / sizeof kParts[0]);

/// The tree, made once: in/ (two frames), out/, and links into it.
const fs::path& tree() {
    static const fs::path root = [] {
        const fs::path r = fs::path(deepsea::fuzz::scratch()) / "tree";
        fs::create_directories(r / "in");
        fs::create_directories(r / "out");
        for (const char* f :
             {"frame_0001.png", "frame_0002.png", "frame_0001_depth.exr", "frame_0002_depth.exr"})
            std::ofstream(r / "in" / f) << "x";
        fs::create_directory_symlink(r / "in", r / "link-in");
        fs::create_directory_symlink(r / "out", r / "link-out");
        fs::create_symlink(r / "in" / "frame_0002.png", r / "link-frame");
        fs::create_symlink(r / "in" / "frame_0001.png", r / "out" / "link-frame");
        fs::create_hard_link(r / "in" / "frame_0002_depth.exr", r / "out" / "hard.png");
        fs::create_symlink(r / "nowhere", r / "dangling");
        return r;
    }();
    return root;
}

/// Every path under the tree (links not followed), to find and undo what a case created.
std::set<std::string> listing() {
    std::set<std::string> out;
    for (auto it = fs::recursive_directory_iterator(tree());
         it != fs::recursive_directory_iterator(); ++it)
        out.insert(it->path().string());
    return out;
}

std::string path_from(const std::uint8_t*& p, const std::uint8_t* end) {
    std::string path = tree().string();
    const int n = p < end ? 1 + *p++ % 5 : 1;
    for (int i = 0; i < n && p < end; ++i) path += std::string("/") + kParts[*p++ % kPartCount];
    return path;
}

[[noreturn]] void landed(const std::string& out, const std::string& in) {
    std::fprintf(stderr, "output %s lands on the input %s\n", out.c_str(), in.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::set<std::string> before = listing();
    const std::uint8_t* p = data;
    const std::uint8_t* end = data + size;
    const bool sequence = p < end && (*p++ & 1);
    const fs::path in = tree() / "in";
    deepsea::FrameFiles files;
    files.rgb = sequence ? (in / "frame_*[0-9].png").string() : (in / "frame_0001.png").string();
    files.depth = sequence ? (in / "*_depth.exr").string() : (in / "frame_0001_depth.exr").string();
    files.output = path_from(p, end);
    if (p < end && (*p++ & 1)) files.layers = path_from(p, end);
    if (!sequence && !files.layers.empty()) files.layers += ".exr";
    std::vector<deepsea::FrameJob> jobs;
    try {
        jobs = deepsea::frame_jobs(files);
    } catch (const deepsea::Error&) {
    }
    if (listing() != before) {
        std::fprintf(stderr, "frame_jobs created files for -o %s\n", files.output.c_str());
        std::abort();
    }
    // What a render would do with the jobs it was given.
    for (const deepsea::FrameJob& j : jobs) {
        for (const std::string& out : {j.output, j.layers}) {
            if (out.empty()) continue;
            std::error_code ec;
            fs::create_directories(fs::path(out).parent_path(), ec);
            fs::path target = out;
            if (fs::is_symlink(out, ec)) target = fs::canonical(out, ec);
            if (ec) continue;  // write_atomically refuses a link that leads nowhere
            struct stat so {
            }, si{};
            const bool exists = ::stat(target.c_str(), &so) == 0;
            for (const deepsea::FrameJob& k : jobs) {
                for (const std::string& input : {k.rgb, k.depth}) {
                    if (deepsea::resolved_path(target.string()) == deepsea::resolved_path(input))
                        landed(out, input);
                    if (exists && ::stat(input.c_str(), &si) == 0 && so.st_dev == si.st_dev &&
                        so.st_ino == si.st_ino)
                        landed(out, input);
                }
            }
        }
    }
    // Undo: remove what the case made (only empty folders can be new).
    const std::set<std::string> after = listing();
    for (auto it = after.rbegin(); it != after.rend(); ++it) {
        if (!before.count(*it)) {
            std::error_code ec;
            fs::remove(*it, ec);
        }
    }
    return 0;
}
