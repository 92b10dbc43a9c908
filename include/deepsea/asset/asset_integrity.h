#pragma once
/// \file The asset file's integrity record (docs/asset-format.md, "Integrity"): its size and a
/// SHA-256 of all its bytes, kept in the file's own metadata and checked over the raw bytes
/// before OpenVDB parses anything, so that a damaged or edited file is refused in one line
/// instead of reaching OpenVDB's decoders.

#include <cstdint>
#include <string>

namespace deepsea {

/// Metadata key of the record (a string) in the file-level metadata.
inline constexpr const char* kMetaIntegrity = "deepsea:integrity";

/// The record's value as written before sealing: "size=" 16 zero digits, " sha256=" 64 zeros.
/// The hash is taken over the file with these digits as zeros.
std::string integrity_placeholder();

/// The record must start within this many bytes of the file (the file metadata comes first).
inline constexpr std::size_t kIntegrityWindow = std::size_t(1) << 20;

struct IntegrityRecord {
    std::uint64_t size = 0;  ///< bytes of the whole file
    std::string sha256;      ///< 64 lowercase hex digits
};

/// Fills in the placeholder record of a complete file held in memory: its size and the SHA-256
/// of the bytes with the placeholder in place. Returns the record. AssetError when `bytes`
/// holds no placeholder record within kIntegrityWindow.
IntegrityRecord seal_asset_bytes(std::string& bytes);

/// Checks the file at `path` against its record, reading only raw bytes (nothing is parsed by
/// OpenVDB). Throws IoError when it cannot be read, AssetError naming `path` when it is not an
/// OpenVDB file, has no record (not a deepsea asset, or one from before the record existed:
/// re-bake it), or its size or hash differ from the record (truncated, damaged or edited).
IntegrityRecord verify_asset_file(const std::string& path);

}  // namespace deepsea
