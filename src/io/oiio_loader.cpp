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

/// The plugin's file name, for the dynamic loader's own search.
constexpr const char* kPluginName = "libdeepsea_oiio.so";

/// True if `p` lies inside the build tree this code was compiled in (an uninstalled program,
/// test or module).
bool in_build_tree(const fs::path& p) {
    std::error_code ec;
    const fs::path build = fs::weakly_canonical(DEEPSEA_BUILD_DIR, ec);
    if (ec) return false;
    const fs::path q = fs::weakly_canonical(p, ec);
    if (ec) return false;
    auto b = build.begin();
    for (auto i = q.begin(); b != build.end(); ++i, ++b)
        if (i == q.end() || *i != *b) return false;
    return true;
}

/// Where to look, in order (docs/install.md, "Static or shared"):
///  1. DEEPSEA_OIIO_PLUGIN alone, if set;
///  2. beside the shared object or program holding this code (dladdr), then beside the running
///     program (/proc/self/exe), as `cmake --install` lays them out: `../lib/deepsea/` from
///     `bin/`, `deepsea/` from `lib/`, so an installed or moved prefix finds its own module;
///  3. the bare name through the dynamic loader's search: LD_LIBRARY_PATH and the run path of
///     the caller, which the CMake package and pkg-config file give a program linked against
///     the static libraries (and the installed Python module has), pointing at the prefix;
///  4. the build tree's module, only for a program or library that lies inside the build tree;
///  5. the configured install prefix's.
std::vector<std::string> candidates() {
    if (const char* env = std::getenv("DEEPSEA_OIIO_PLUGIN"); env && *env) return {env};
    std::vector<fs::path> files;
    std::error_code ec;
    Dl_info info{};
    // A shared object's name is absolute; the program's is its argv[0], which may be relative
    // to a PATH entry rather than to the working folder: /proc/self/exe gives the program.
    if (dladdr(reinterpret_cast<void*>(&candidates), &info) != 0 && info.dli_fname &&
        fs::path(info.dli_fname).is_absolute())
        files.push_back(info.dli_fname);
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) files.push_back(exe);
    std::vector<std::string> out;
    const auto add = [&](const fs::path& p) {
        const std::string s = p.lexically_normal().string();
        for (const std::string& o : out)
            if (o == s) return;
        out.push_back(s);
    };
    for (const fs::path& f : files) {
        add(f.parent_path() / DEEPSEA_OIIO_PLUGIN_FROM_BINDIR);
        add(f.parent_path() / DEEPSEA_OIIO_PLUGIN_FROM_LIBDIR);
    }
    add(kPluginName);
    for (const fs::path& f : files) {
        if (in_build_tree(f)) {
            add(DEEPSEA_OIIO_PLUGIN_BUILD);
            break;
        }
    }
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
        const bool by_name = path == kPluginName;  // the loader searches; no file to check
        if (!by_name && !fs::exists(path, ec)) {
            refused(path + ": no such file");
            continue;
        }
        void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            refused((by_name ? "the loader's search: " : "") + (e ? std::string(e) : path));
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
