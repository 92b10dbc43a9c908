// Finds and loads libdeepsea_oiio.so (oiio_plugin.h) the first time an image needs OpenImageIO.

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "file_checks.h"
#include "oiio_plugin.h"

namespace deepsea::io_detail {

namespace fs = std::filesystem;

namespace {

struct Loaded {
    const OiioPlugin* plugin = nullptr;
    std::string why;  ///< every place tried and why each failed, when plugin is null
};

/// Where to look, in order: DEEPSEA_OIIO_PLUGIN alone if set; else beside the program or the
/// library holding this code, as `cmake --install` lays them out (so an installed or moved
/// prefix finds its own module); else the build tree's and the configured prefix's paths.
std::vector<std::string> candidates() {
    if (const char* env = std::getenv("DEEPSEA_OIIO_PLUGIN"); env && *env) return {env};
    std::vector<fs::path> dirs;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) dirs.push_back(exe.parent_path());
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&candidates), &info) != 0 && info.dli_fname) {
        const fs::path self = fs::absolute(info.dli_fname, ec);
        if (!ec) dirs.push_back(self.parent_path());
    }
    std::vector<std::string> out;
    const auto add = [&](const fs::path& p) {
        const std::string s = p.lexically_normal().string();
        for (const std::string& o : out)
            if (o == s) return;
        out.push_back(s);
    };
    for (const fs::path& d : dirs) {
        add(d / DEEPSEA_OIIO_PLUGIN_FROM_BINDIR);
        add(d / DEEPSEA_OIIO_PLUGIN_FROM_LIBDIR);
    }
    add(DEEPSEA_OIIO_PLUGIN_BUILD);
    add(DEEPSEA_OIIO_PLUGIN_INSTALL);
    return out;
}

Loaded load() {
    Loaded l;
    const auto refused = [&](const std::string& why) {
        l.why += (l.why.empty() ? "" : "; ") + why;
    };
    for (const std::string& path : candidates()) {
        std::error_code ec;
        if (!fs::exists(path, ec)) {
            refused(path + ": no such file");
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            refused(e ? std::string(e) : path);
            continue;
        }
        using Entry = const OiioPlugin* (*)();
        const auto entry = reinterpret_cast<Entry>(dlsym(handle, "deepsea_oiio_plugin"));
        const OiioPlugin* p = entry ? entry() : nullptr;
        if (p && p->abi == kOiioPluginAbi) {
            l.plugin = p;  // never unloaded: OpenImageIO keeps threads and caches
            return l;
        }
        refused(path + ": not a module of this deepsea version");
        dlclose(handle);
    }
    return l;
}

}  // namespace

const OiioPlugin& oiio(const std::string& path) {
    static const Loaded loaded = load();
    if (!loaded.plugin) {
        io_fail(path,
                "this format needs OpenImageIO, and deepsea's OpenImageIO module "
                "(libdeepsea_oiio.so) could not be loaded: " +
                    loaded.why);
    }
    return *loaded.plugin;
}

}  // namespace deepsea::io_detail
