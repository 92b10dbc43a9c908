#include "deepsea/runtime/frame_jobs.h"

#include <glob.h>

#include <algorithm>
#include <filesystem>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

}  // namespace

bool is_pattern(const std::string& path) { return path.find_first_of("*?[") != std::string::npos; }

std::vector<FrameJob> frame_jobs(const FrameFiles& f) {
    namespace fs = std::filesystem;
    if (!is_pattern(f.rgb)) {
        if (is_pattern(f.depth))
            throw ConfigError("colour input '" + f.rgb + "' is one file but depth input '" +
                              f.depth + "' is a pattern");
        return {{f.rgb, f.depth, f.output, f.layers}};
    }
    std::vector<FrameJob> jobs =
        pair_frames(glob_files(f.rgb), glob_files(f.depth), f.rgb, f.depth);
    for (const std::string& dir : {f.output, f.layers}) {
        if (dir.empty()) continue;
        std::error_code ec;
        fs::create_directories(dir, ec);
        if (ec || !fs::is_directory(dir)) throw IoError("cannot create output folder " + dir);
    }
    for (FrameJob& j : jobs) {
        if (!f.output.empty()) j.output = (fs::path(f.output) / (stem(j.rgb) + ".png")).string();
        if (!f.layers.empty()) j.layers = (fs::path(f.layers) / (stem(j.rgb) + ".exr")).string();
    }
    return jobs;
}

std::vector<std::string> glob_files(const std::string& pattern) {
    glob_t g{};
    std::vector<std::string> out;
    if (::glob(pattern.c_str(), 0, nullptr, &g) == 0) {
        for (std::size_t i = 0; i < g.gl_pathc; ++i) out.emplace_back(g.gl_pathv[i]);
    }
    globfree(&g);
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<FrameJob> pair_frames(std::vector<std::string> rgb, std::vector<std::string> depth,
                                  const std::string& rgb_pattern,
                                  const std::string& depth_pattern) {
    if (rgb.empty()) throw InputError("no colour files match '" + rgb_pattern + "'");
    if (depth.empty()) throw InputError("no depth files match '" + depth_pattern + "'");
    // A pattern like 'dir/*.png' may also match nothing else; depth files are often named
    // <frame>_depth.exr: drop them from the colour list if both patterns caught them.
    std::sort(rgb.begin(), rgb.end());
    std::sort(depth.begin(), depth.end());
    std::vector<std::string> rgb_only;
    for (const auto& f : rgb) {
        if (!std::binary_search(depth.begin(), depth.end(), f)) rgb_only.push_back(f);
    }
    if (rgb_only.size() != depth.size()) {
        throw InputError(std::to_string(rgb_only.size()) + " colour files ('" + rgb_pattern +
                         "') but " + std::to_string(depth.size()) + " depth files ('" +
                         depth_pattern + "')");
    }
    std::vector<FrameJob> jobs(rgb_only.size());
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        jobs[i].rgb = rgb_only[i];
        jobs[i].depth = depth[i];
    }
    return jobs;
}

}  // namespace deepsea
