#include "deepsea/batch/frame_jobs.h"

#include <glob.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <map>
#include <regex>
#include <set>

#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/hash.h"
#include "deepsea/io/image_io.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

std::string stem(const std::string& path) { return fs::path(path).stem().string(); }

/// A frame-number token at p[i]: `%d`, `%04d` (`%4d`) or a run of '#' (`####`): its length in
/// `p` and the fewest digits it stands for (printf's width: more digits also match). Length 0:
/// none.
struct NumberToken {
    std::size_t length = 0;
    int digits = 0;
};

NumberToken number_token(const std::string& p, std::size_t i) {
    if (p[i] == '#') {
        const std::size_t end = std::min(p.find_first_not_of('#', i), p.size());
        return {end - i, int(end - i)};
    }
    if (p[i] != '%') return {};
    std::size_t j = i + 1;
    while (j < p.size() && j - i <= 3 && std::isdigit(static_cast<unsigned char>(p[j]))) ++j;
    if (j >= p.size() || p[j] != 'd') return {};
    const int width = j > i + 1 ? std::atoi(p.substr(i + 1, j - i - 1).c_str()) : 1;
    return {j + 1 - i, std::max(width, 1)};
}

bool has_number_token(const std::string& p) {
    for (std::size_t i = 0; i < p.size(); ++i)
        if (number_token(p, i).length > 0) return true;
    return false;
}

/// The pattern with each number token as '*': what glob lists and what name keys read.
std::string as_glob(const std::string& p) {
    std::string out;
    for (std::size_t i = 0; i < p.size();) {
        const NumberToken t = number_token(p, i);
        out += t.length ? std::string("*") : std::string(1, p[i]);
        i += t.length ? t.length : 1;
    }
    return out;
}

/// The whole pattern as a regular expression: glob wildcards within one path component,
/// number tokens as their digits.
std::regex as_regex(const std::string& p) {
    std::string re;
    for (std::size_t i = 0; i < p.size();) {
        const NumberToken t = number_token(p, i);
        if (t.length) {
            re += "[0-9]{" + std::to_string(t.digits) + ",}";
            i += t.length;
            continue;
        }
        const char c = p[i++];
        if (c == '*') {
            re += "[^/]*";
        } else if (c == '?') {
            re += "[^/]";
        } else if (c == '[' && p.find(']', i + 1) != std::string::npos) {
            const std::size_t close = p.find(']', i + 1);  // "[]a]" holds ']'
            std::string set;
            for (const char ch : p.substr(i, close - i))
                set += ch == '\\' ? std::string("\\\\") : std::string(1, ch);
            if (!set.empty() && set[0] == '!') set[0] = '^';
            re += "[" + set + "]";
            i = close + 1;
        } else {
            if (std::string(".^$|()+{}[]\\").find(c) != std::string::npos) re += '\\';
            re += c;
        }
    }
    return std::regex(re);
}

/// Key by name: the stem less the fixed text the pattern's file name puts before its first and
/// after its last wildcard.
std::string name_key(const std::string& path, const std::string& pattern) {
    std::string key = stem(path);
    const std::string p = fs::path(pattern).stem().string();
    const std::size_t first = p.find_first_of("*?[");
    if (first == std::string::npos) return key;
    const std::string prefix = p.substr(0, first), suffix = p.substr(p.find_last_of("*?]") + 1);
    if (key.size() >= prefix.size() + suffix.size() && key.compare(0, prefix.size(), prefix) == 0 &&
        key.compare(key.size() - suffix.size(), suffix.size(), suffix) == 0) {
        key = key.substr(prefix.size(), key.size() - prefix.size() - suffix.size());
    }
    return key;
}

/// Key by number: the last run of digits in the stem, without leading zeros; empty if none.
std::string number_key(const std::string& path, const std::string&) {
    const std::string s = stem(path);
    const std::size_t end = s.find_last_of("0123456789");
    if (end == std::string::npos) return {};
    std::size_t begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(s[begin - 1]))) --begin;
    const std::string digits = s.substr(begin, end + 1 - begin);
    const std::size_t nz = digits.find_first_not_of('0');
    return nz == std::string::npos ? "0" : digits.substr(nz);
}

/// How one keying pairs the two lists.
struct Pairing {
    std::vector<FrameJob> jobs;
    std::vector<std::string> lone_rgb, lone_depth;
    std::string duplicate;  ///< "a and b" with the same key, if any
};

Pairing pair_by(const std::vector<std::string>& rgb, const std::vector<std::string>& depth,
                const std::string& rgb_pattern, const std::string& depth_pattern,
                const std::function<std::string(const std::string&, const std::string&)>& key) {
    Pairing p;
    std::map<std::string, std::string> by_key;
    for (const auto& d : depth) {
        const std::string k = key(d, depth_pattern);
        if (k.empty()) {
            p.lone_depth.push_back(d);
        } else if (!by_key.emplace(k, d).second && p.duplicate.empty()) {
            p.duplicate = "depth files " + by_key[k] + " and " + d + " are both frame '" + k + "'";
        }
    }
    std::map<std::string, std::string> rgb_by_key;
    for (const auto& c : rgb) {
        const std::string k = key(c, rgb_pattern);
        if (!k.empty() && !rgb_by_key.emplace(k, c).second && p.duplicate.empty()) {
            p.duplicate =
                "colour files " + rgb_by_key[k] + " and " + c + " are both frame '" + k + "'";
        }
        const auto it = k.empty() ? by_key.end() : by_key.find(k);
        if (it == by_key.end()) {
            p.lone_rgb.push_back(c);
        } else {
            p.jobs.push_back({c, it->second, "", "", std::nullopt, std::nullopt});
        }
    }
    for (const auto& [k, d] : by_key) {
        if (!rgb_by_key.count(k)) p.lone_depth.push_back(d);
    }
    std::sort(p.lone_depth.begin(), p.lone_depth.end());
    return p;
}

std::string list(const std::vector<std::string>& files) {
    std::string out;
    const std::size_t shown = std::min<std::size_t>(files.size(), 5);
    for (std::size_t i = 0; i < shown; ++i) out += (i ? ", " : "") + files[i];
    if (files.size() > shown) out += " and " + std::to_string(files.size() - shown) + " more";
    return out;
}

void check_not_input(const std::string& out, const char* flag, const FrameFiles& f) {
    for (const auto& [input, what] : {std::pair{f.rgb, "colour"}, std::pair{f.depth, "depth"}}) {
        if (same_file(out, input)) {
            throw ConfigError(out + ": " + flag + " is also the " + what +
                              " input; it would be overwritten");
        }
    }
}

/// One frame's output file: a format OpenImageIO writes, in an existing writable folder.
void check_output_file(const std::string& path, const char* flag, const FrameFiles& f) {
    if (path.empty()) return;
    check_not_input(path, flag, f);
    if (std::string(flag) == "--layers") {
        std::string ext = fs::path(path).extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        if (ext != ".exr") {
            throw ConfigError(path + ": --layers writes a multi-layer OpenEXR file: use .exr");
        }
    } else {
        require_image_writer(path);
    }
    if (fs::is_directory(path)) throw ConfigError(path + ": " + flag + " is a folder, not a file");
    require_writable_folder(path);
}

/// A sequence's output folder: a folder or a name that can become one, never an input folder.
void check_output_folder(const std::string& dir, const char* flag,
                         const std::vector<FrameJob>& jobs) {
    if (dir.empty()) return;
    // Compared as the system resolves them, whether or not the folder exists yet: "in/x/..",
    // "./in/" and a link to "in" are all "in".
    const fs::path folder = resolved_path(dir);
    for (const FrameJob& j : jobs) {
        for (const std::string& in : {j.rgb, j.depth}) {
            // The folder the input is named in, and the one it is in (if it is a link).
            const std::string named = fs::path(in).parent_path().string();
            if (resolved_path(named.empty() ? "." : named) == folder ||
                resolved_path(in).parent_path() == folder) {
                throw ConfigError(dir + ": " + flag + " is the folder of the input " + in +
                                  "; write the sequence into another folder");
            }
        }
    }
    std::error_code ec;
    if (fs::exists(dir, ec)) {
        if (!fs::is_directory(dir, ec)) {
            throw ConfigError(dir + ": " + flag +
                              " of a sequence must be a folder, and this is a file");
        }
        if (::access(dir.c_str(), W_OK) != 0) {
            throw IoError(dir + ": cannot write into the folder: " + std::strerror(errno));
        }
        return;
    }
    if (has_image_writer(dir)) {
        throw ConfigError(dir + ": " + flag +
                          " of a sequence names a folder (one file per frame goes into it), "
                          "not an image file");
    }
    fs::path p = fs::absolute(dir).parent_path();
    while (!p.empty() && !fs::exists(p, ec) && p != p.parent_path()) p = p.parent_path();
    if (!fs::is_directory(p, ec)) {
        throw IoError(dir + ": cannot create the folder: " + p.string() + " is not a folder");
    }
    if (::access(p.c_str(), W_OK) != 0) {
        throw IoError(dir + ": cannot create the folder in " + p.string() + ": " +
                      std::strerror(errno));
    }
}

/// No output may be an input under another name (a link in the output folder to a frame, a
/// hard link): the files' identities, device and inode, are compared, n log n for any count.
void check_outputs_are_not_inputs(const std::vector<FrameJob>& jobs) {
    std::set<std::pair<dev_t, ino_t>> inputs;
    struct stat st {};
    for (const FrameJob& j : jobs) {
        for (const std::string* in : {&j.rgb, &j.depth})
            if (::stat(in->c_str(), &st) == 0) inputs.emplace(st.st_dev, st.st_ino);
    }
    for (const FrameJob& j : jobs) {
        for (const std::string* out : {&j.output, &j.layers}) {
            if (!out->empty() && ::stat(out->c_str(), &st) == 0 &&
                inputs.count({st.st_dev, st.st_ino})) {
                throw ConfigError(*out +
                                  ": is one of this render's input files (under another "
                                  "name or through a link); it would be overwritten");
            }
        }
    }
}

}  // namespace

std::uint64_t frame_key(const FrameJob& job) { return fnv1a64(stem(job.rgb)); }

bool FrameFiles::sequence() const { return is_pattern(rgb); }

bool is_pattern(const std::string& path) {
    if (path.find_first_of("*?[") != std::string::npos) return true;
    std::error_code ec;
    return has_number_token(path) && !fs::exists(path, ec);  // a file may hold '#' or '%'
}

std::vector<FrameJob> frame_jobs(const FrameFiles& f) {
    if (f.output.empty() && f.layers.empty()) {
        throw ConfigError("nothing to write: give -o and/or --layers");
    }
    const std::string format = f.format.empty() ? "png" : f.format;
    if (format != "png" && format != "jpg" && format != "tif" && format != "exr") {
        throw ConfigError("--format " + f.format + ": expected png, jpg, tif or exr");
    }
    if (!f.sequence()) {
        if (is_pattern(f.depth))
            throw ConfigError("colour input '" + f.rgb + "' is one file but depth input '" +
                              f.depth + "' is a pattern");
        check_output_file(f.output, "-o", f);
        check_output_file(f.layers, "--layers", f);
        if (!f.format.empty() && !f.output.empty() && image_format(f.output) != f.format) {
            throw ConfigError(f.output + ": -o is not a ." + f.format + " file but --format is " +
                              f.format);
        }
        if (!f.output.empty() && !f.layers.empty() && same_file(f.output, f.layers)) {
            throw ConfigError(f.output + ": -o and --layers name the same file");
        }
        std::vector<FrameJob> one{{f.rgb, f.depth, f.output, f.layers, std::nullopt, std::nullopt}};
        check_outputs_are_not_inputs(one);
        return one;
    }
    std::vector<FrameJob> jobs =
        pair_frames(glob_files(f.rgb), glob_files(f.depth), f.rgb, f.depth);
    check_output_folder(f.output, "-o", jobs);
    check_output_folder(f.layers, "--layers", jobs);
    std::map<std::string, const FrameJob*> written;
    for (FrameJob& j : jobs) {
        if (!f.output.empty())
            j.output = (fs::path(f.output) / (stem(j.rgb) + "." + format)).string();
        if (!f.layers.empty()) j.layers = (fs::path(f.layers) / (stem(j.rgb) + ".exr")).string();
        for (const std::string* out : {&j.output, &j.layers}) {
            if (out->empty()) continue;
            const auto [it, fresh] = written.emplace(*out, &j);
            if (!fresh) {
                throw ConfigError(*out + ": both " + it->second->rgb + " and " + j.rgb +
                                  " would be written here; render them into separate folders");
            }
        }
    }
    check_outputs_are_not_inputs(jobs);
    return jobs;
}

std::vector<std::string> glob_files(const std::string& pattern) {
    glob_t g{};
    std::vector<std::string> out;
    const bool numbered = has_number_token(pattern);
    const std::regex numbers = numbered ? as_regex(pattern) : std::regex();
    if (::glob(as_glob(pattern).c_str(), 0, nullptr, &g) == 0) {
        for (std::size_t i = 0; i < g.gl_pathc; ++i)
            if (!numbered || std::regex_match(g.gl_pathv[i], numbers))
                out.emplace_back(g.gl_pathv[i]);
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
    // A pattern like 'dir/*' may also catch the depth files (often <frame>_depth.exr): drop
    // them from the colour list if both patterns caught them.
    std::sort(rgb.begin(), rgb.end());
    std::sort(depth.begin(), depth.end());
    std::vector<std::string> rgb_only;
    for (const auto& f : rgb) {
        if (!std::binary_search(depth.begin(), depth.end(), f)) rgb_only.push_back(f);
    }
    if (rgb_only.empty()) throw InputError("no colour files match '" + rgb_pattern + "'");
    // By name first; by number where the names differ (rgb_0001.png, depth_0001.exr).
    const std::string rgb_glob = as_glob(rgb_pattern), depth_glob = as_glob(depth_pattern);
    const Pairing by_name = pair_by(rgb_only, depth, rgb_glob, depth_glob, name_key);
    const Pairing by_number = pair_by(rgb_only, depth, rgb_glob, depth_glob, number_key);
    for (const Pairing* p : {&by_name, &by_number}) {
        if (p->duplicate.empty() && p->lone_rgb.empty() && p->lone_depth.empty()) return p->jobs;
    }
    // Report what the keying that paired the most files found.
    const Pairing& best = by_number.duplicate.empty() && by_number.jobs.size() > by_name.jobs.size()
                              ? by_number
                              : by_name;
    if (!best.duplicate.empty()) throw InputError(best.duplicate + ": cannot pair frames");
    std::string msg = "unpaired frames (colour and depth pair by file name or frame number):";
    if (!best.lone_rgb.empty()) {
        msg += " " + std::to_string(best.lone_rgb.size()) + " colour file(s) without depth ('" +
               depth_pattern + "'): " + list(best.lone_rgb);
        if (!best.lone_depth.empty()) msg += ";";
    }
    if (!best.lone_depth.empty()) {
        msg += " " + std::to_string(best.lone_depth.size()) + " depth file(s) without colour ('" +
               rgb_pattern + "'): " + list(best.lone_depth);
    }
    throw InputError(msg);
}

}  // namespace deepsea
