#pragma once
/// \file The asset's `.vdb` file (docs/asset-format.md): grid `backscatter` (Vec3f, index
/// (i, j, k), an affine transform into the frustum's bounding box, its camera-space geometry in
/// metadata), the preview grid `density` (the lamps' beams) on a world-space linear grid,
/// metadata `deepsea:format` and `deepsea:bake`.
/// OpenVDB stays behind this header; errors are AssetError (what is in the file) or IoError
/// (the file system).

#include <cstdint>
#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/core/vec.h"

namespace deepsea {

/// Grid names in the file. The backscatter lookup table's name sorts after `density`: OpenVDB
/// lists a file's grids by name and Blender shows the first one in its viewport, which must be
/// the beams (docs/blender.md). Assets before format 3 call it `backscatter`
/// (kOldBackscatterGrid), and are read as before.
inline constexpr const char* kBackscatterGrid = "water_backscatter";
inline constexpr const char* kOldBackscatterGrid = "backscatter";
/// The lamps' beams (Blender's Principled Volume reads `density` by default).
inline constexpr const char* kDensityGrid = "density";
/// Prefix of the multiple-scattering lamp tables: lamp_field_0, lamp_field_1, ...
inline constexpr const char* kLampFieldGrid = "lamp_field_";

struct WriteOptions {
    /// Store the backscatter grid as 16-bit half floats (OpenVDB's saveFloatAsHalf). Values
    /// are scaled by a power of two first so that they sit in half's normal range; the loader
    /// undoes it exactly (`deepsea:value_scale`).
    bool half = true;
    /// Write the `density` preview grid (the lamps' beams) for Blender and Houdini.
    bool preview = true;
    /// Preview voxels along the longest side of the beams' box (docs/asset-format.md).
    int preview_resolution = 128;
};

/// ConfigError unless OpenVDB can store an asset of this camera and lattice: the backscatter
/// grid's and the lamp tables' transforms (OpenVDB refuses a linear map whose cells are below
/// about 14 micrometres on average as "nearly singular"). bake() calls it before it computes
/// any column, so that such a lattice costs no work; write_asset reports the same as an
/// AssetError.
void check_storable(const Camera& camera, const Lattice& lattice);

/// Writes the asset atomically: to a temporary file in the same directory, then a rename, so
/// readers never see a partial file and a failure leaves none. Throws IoError when the
/// directory is missing or unwritable or the disk is full, AssetError when the asset is
/// inconsistent (values do not match the lattice).
void write_asset(const std::string& path, const Asset& asset, const WriteOptions& opt = {});

/// Reads a whole asset into flat arrays. Throws IoError when the file cannot be opened, and
/// AssetError for a file that is not a VDB, is truncated, has no or a newer `deepsea:format`,
/// or whose grid does not match its `deepsea:bake` lattice.
Asset load_asset(const std::string& path);

/// One grid of an asset file, from its metadata (no voxel data read).
struct GridSummary {
    std::string name;
    std::string value_type;  ///< "vec3s", "float", ...
    std::string transform;   ///< "frustum" or "linear"
    bool half = false;       ///< stored as 16-bit floats
    std::int64_t active_voxels = 0;
    Vec3 world_min, world_max;  ///< world-space bounding box of the active voxels
    /// The same for OpenVDB's leaf nodes (8^3 voxels) around them: what Blender frames.
    Vec3 leaf_world_min, leaf_world_max;
};

/// What `deepsea info` shows besides the values.
struct AssetFileSummary {
    std::uintmax_t file_bytes = 0;
    std::string sha256;  ///< of the whole file, as verified (asset_integrity.h)
    int format = 0;
    BakeInfo info;
    double value_scale = 1.0;          ///< stored backscatter = radiance * value_scale
    double preview_voxel_size = 0.0;   ///< metres; 0 without preview grids
    double preview_density_scale = 0;  ///< scattered power (luminance, W/m^3) at density 1
    std::vector<GridSummary> grids;
};

/// Reads the metadata only (fast). Same errors as load_asset, except that it does not read
/// (or check) the voxel data.
AssetFileSummary read_asset_summary(const std::string& path);

/// Maps index-space points of a grid in the file to world space with the grid's own OpenVDB
/// transform, as vdb_print or Houdini would. For tests and inspection.
std::vector<Vec3> index_to_world(const std::string& path, const std::string& grid,
                                 const std::vector<Vec3>& index_points);

/// The world frame of the file's transforms: OpenGL-style camera frame, x right, y up,
/// looking down -z. A camera-frame (OpenCV) point maps to (x, -y, -z).
inline Vec3 camera_to_world(const Vec3& p) { return {p.x, -p.y, -p.z}; }

/// An axis-aligned box in the file's world frame, metres.
struct WorldBox {
    Vec3 min, max;
};

/// The frustum's extent: the world bounding box of the camera's view (the image's outer pixel
/// edges, -0.5 .. width - 0.5) from the camera centre to planar depth z_max. Every grid of an
/// asset lies in it, with OpenVDB's leaf nodes (what Blender frames) included.
WorldBox frustum_extent(const Camera& camera, double z_max);

/// True if the asset at `path` reads and was written by this deepsea's format
/// (`kAssetFormat`) for the inputs `input_hash` (BakeInfo::input_hash): nothing to re-bake.
/// False for a missing, unreadable or older asset.
bool asset_up_to_date(const std::string& path, const std::string& input_hash);

/// Throws IoError unless `path` can be created or replaced: it ends in `.vdb` (an asset under
/// another name, say x.exr, would only mislead), its directory exists and is writable, and it
/// is not a folder. write_asset checks this itself; call it before a long bake to fail early.
void require_writable(const std::string& path);

}  // namespace deepsea
