// libFuzzer target: the YAML readers (src/io/yaml_reader.cpp under config.cpp and
// library_manifest.cpp). Any input must give a Setup / manifest or a deepsea::Error; anything
// else escaping (a yaml-cpp or std exception), a crash or a sanitizer report is a bug.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/io/library_manifest.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::optional<deepsea::Setup> setup;
    try {
        setup = deepsea::parse_setup(text, "fuzz.yaml");
    } catch (const deepsea::Error&) {
    }
    if (setup) {
        // What parses must print and parse back (import-config and bake write it this way).
        const std::string again = deepsea::setup_to_yaml(*setup);
        try {
            (void)deepsea::parse_setup(again, "fuzz-again.yaml");
        } catch (const deepsea::Error& e) {
            std::fprintf(stderr, "setup_to_yaml wrote what parse_setup refuses: %s\n%s\n", e.what(),
                         again.c_str());
            std::abort();
        }
    }
    try {
        // Relative paths resolve against the scratch folder, which holds no configs.
        (void)deepsea::parse_library_manifest(text, "fuzz-library.yaml", deepsea::fuzz::scratch());
    } catch (const deepsea::Error&) {
    }
    return 0;
}
