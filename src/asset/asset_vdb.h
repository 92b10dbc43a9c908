#pragma once
// Internal to the asset's file: the metadata names, checksum and OpenVDB helpers that writing
// (asset_write.cpp) and reading (asset_file.cpp) share. OpenVDB is slow to compile: only those
// two translation units include this.

#include <openvdb/openvdb.h>

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>

#include "deepsea/asset/asset_file.h"
#include "deepsea/core/hash.h"

namespace deepsea::asset_vdb {

namespace vdb = openvdb;

inline constexpr const char* kMetaFormat = "deepsea:format";
inline constexpr const char* kMetaBake = "deepsea:bake";
inline constexpr const char* kMetaScale = "deepsea:value_scale";
inline constexpr const char* kMetaChecksum = "deepsea:checksum";
inline constexpr const char* kMetaZ = "deepsea:z_samples";
/// The forward-scatter table from transport (forward_psf_json.h); absent: the small-angle model.
inline constexpr const char* kMetaForwardPsf = "deepsea:forward_psf";
inline constexpr const char* kMetaPreviewVoxel = "deepsea:preview_voxel_size";
inline constexpr const char* kMetaPreviewScale = "deepsea:preview_density_scale";

inline void init_openvdb() {
    static std::once_flag once;
    std::call_once(once, [] { vdb::initialize(); });
}

/// FNV-1a over the bit patterns of the stored floats: OpenVDB does not notice every truncated
/// or damaged file (a short read can leave zeros), so the loader compares this.
inline std::uint64_t checksum(const float* v, std::size_t n) {
    // Little-endian bytes of each float, as the files written on x86 and ARM hold them.
    std::uint64_t h = kFnv1aBasis;
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t bits;
        std::memcpy(&bits, &v[i], 4);
        const unsigned char b[4] = {
            static_cast<unsigned char>(bits), static_cast<unsigned char>(bits >> 8),
            static_cast<unsigned char>(bits >> 16), static_cast<unsigned char>(bits >> 24)};
        h = fnv1a64(b, 4, h);
    }
    return h;
}

inline std::string hex(std::uint64_t h) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

template <typename T>
bool get_meta(const vdb::MetaMap& meta, const char* name, T& out) {
    using MetaT = vdb::TypedMetadata<T>;
    const auto m = meta.getMetadata<MetaT>(name);
    if (!m) return false;
    out = m->value();
    return true;
}

/// Grid name of lamp l's scattered-light table.
inline std::string lamp_field_grid(std::size_t l) { return kLampFieldGrid + std::to_string(l); }

inline constexpr const char* kMetaFieldR0 = "deepsea:r0";
inline constexpr const char* kMetaFieldRMax = "deepsea:r_max";
inline constexpr const char* kMetaFieldError = "deepsea:rel_std_error";

}  // namespace deepsea::asset_vdb
