// libFuzzer target: the asset loader (src/asset/asset_file.cpp) on in-memory .vdb bytes.
//
// Built twice (tests/fuzz/CMakeLists.txt):
// - fuzz_asset: the bytes as they are. Nearly every mutation is stopped by the whole-file
//   SHA-256 (asset_integrity.h) before OpenVDB parses anything: this fuzzes that gate.
// - fuzz_asset_sealed (DEEPSEA_FUZZ_RESEAL): the mutated bytes are re-sealed with a valid
//   record first, as a deliberate forger would, so that OpenVDB's parse and deepsea's checks
//   after it (metadata JSON, grid type and bounds, value checksum) see the mutations.
// Any input must give an asset or a deepsea::Error.

#include <cstddef>
#include <cstdint>
#include <string>

#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_integrity.h"
#include "deepsea/core/error.h"
#include "fuzz_util.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#ifdef DEEPSEA_FUZZ_RESEAL
    std::string bytes(reinterpret_cast<const char*>(data), size);
    try {
        deepsea::seal_asset_bytes(bytes);
    } catch (const deepsea::AssetError&) {
        // No placeholder record left: the loader refuses it as the plain target would.
    }
    const std::string path = deepsea::fuzz::write_input(
        "asset.vdb", reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
#else
    const std::string path = deepsea::fuzz::write_input("asset.vdb", data, size);
#endif
    try {
        (void)deepsea::load_asset(path);
    } catch (const deepsea::Error&) {
    }
    try {
        (void)deepsea::read_asset_summary(path);
    } catch (const deepsea::Error&) {
    }
    return 0;
}
