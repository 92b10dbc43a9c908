// Reading the asset's file: its checks, its grids into flat arrays, its summary (writing it is
// asset_write.cpp).

#include "deepsea/asset/asset_file.h"

#include <openvdb/io/File.h>
#include <openvdb/math/Maps.h>
#include <openvdb/math/Transform.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "asset_vdb.h"
#include "deepsea/asset/asset_integrity.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"
#include "deepsea/core/input_file.h"
#include "forward_psf_json.h"

namespace deepsea {

namespace fs = std::filesystem;
namespace vdb = openvdb;
using namespace asset_vdb;

namespace {

/// `path` once it names a regular asset file: a device or a pipe would never end, and a name
/// with a NUL character (from Python) would open another file. Assets beyond 64 GB are
/// refused: a 4K camera's lattice with every grid is a few hundred megabytes.
const std::string& checked(const std::string& path) {
    require_input_file(path, std::uintmax_t(64) << 30, "an asset");
    return path;
}

/// The backscatter grid's name in an open file: format 3's, or before it `backscatter`.
const char* backscatter_grid_name(vdb::io::File& file) {
    return file.hasGrid(kOldBackscatterGrid) && !file.hasGrid(kBackscatterGrid)
               ? kOldBackscatterGrid
               : kBackscatterGrid;
}

/// An open file and its deepsea metadata (file-level first, else the backscatter grid's,
/// which survives when Houdini re-saves the grid).
struct OpenAsset {
    vdb::io::File file;
    vdb::MetaMap meta;
    int format = 0;
    BakeInfo info;
    double value_scale = 1.0;
    IntegrityRecord record;

    explicit OpenAsset(const std::string& path) : file(checked(path)) {
        init_openvdb();
        // Every byte is checked before OpenVDB parses any: its decoders trust lengths in the
        // file (a changed byte can make them overflow a buffer or allocate gigabytes).
        record = verify_asset_file(path);
        try {
            file.open(/*delayLoad=*/false);  // no memory map: a truncated file cannot SIGBUS
        } catch (const std::exception& e) {
            throw AssetError(path + ": not an OpenVDB file (" + one_line(e.what()) + ")");
        }
        try {
            meta = *file.getMetadata();
            std::int32_t f = 0;
            if (!get_meta(meta, kMetaFormat, f)) {
                const char* grid = backscatter_grid_name(file);
                if (file.hasGrid(grid)) {
                    meta = *file.readGridMetadata(grid);
                    get_meta(meta, kMetaFormat, f);
                }
            }
            format = f;
        } catch (const std::exception& e) {
            throw AssetError(path + ": damaged OpenVDB file (" + one_line(e.what()) + ")");
        }
        if (format == 0)
            throw AssetError(path + ": not a deepsea asset (no deepsea:format metadata)");
        if (format < 0 || format > kAssetFormat) {
            throw AssetError(path + ": asset format " + std::to_string(format) +
                             " is not one this deepsea reads (1.." + std::to_string(kAssetFormat) +
                             "); update deepsea or re-bake");
        }
        std::string json;
        if (!get_meta(meta, kMetaBake, json)) throw AssetError(path + ": no deepsea:bake metadata");
        try {
            info = bake_info_from_json(json);
        } catch (const AssetError& e) {
            throw AssetError(path + ": " + one_line(e.what()));
        }
        get_meta(meta, kMetaScale, value_scale);
        if (!(value_scale > 0.0)) throw AssetError(path + ": bad deepsea:value_scale");
    }
};

GridSummary summarize(const vdb::GridBase& g) {
    GridSummary s;
    s.name = g.getName();
    s.value_type = g.valueType();
    s.transform =
        g.transform().mapType() == vdb::math::NonlinearFrustumMap::mapType() ? "frustum" : "linear";
    s.half = g.saveFloatAsHalf();
    if (auto c = g.getMetadata<vdb::Int64Metadata>(vdb::GridBase::META_FILE_VOXEL_COUNT)) {
        s.active_voxels = c->value();
    }
    const auto lo = g.getMetadata<vdb::Vec3IMetadata>(vdb::GridBase::META_FILE_BBOX_MIN);
    const auto hi = g.getMetadata<vdb::Vec3IMetadata>(vdb::GridBase::META_FILE_BBOX_MAX);
    if (lo && hi && s.active_voxels > 0) {
        const auto world = [&](const vdb::Vec3i& a, const vdb::Vec3i& b, Vec3& wmin, Vec3& wmax) {
            const vdb::BBoxd w = g.transform().indexToWorld(
                vdb::BBoxd(vdb::Vec3d(a.x(), a.y(), a.z()), vdb::Vec3d(b.x(), b.y(), b.z())));
            wmin = {w.min().x(), w.min().y(), w.min().z()};
            wmax = {w.max().x(), w.max().y(), w.max().z()};
        };
        world(lo->value(), hi->value(), s.world_min, s.world_max);
        // The leaf nodes around the active voxels (an 8^3 leaf's origin is a multiple of 8).
        const auto leaf_lo = [](int x) { return x & ~7; };
        const vdb::Vec3i a = lo->value(), b = hi->value();
        world({leaf_lo(a.x()), leaf_lo(a.y()), leaf_lo(a.z())},
              {leaf_lo(b.x()) + 7, leaf_lo(b.y()) + 7, leaf_lo(b.z()) + 7}, s.leaf_world_min,
              s.leaf_world_max);
    }
    return s;
}

LampField lamp_field_from_file(vdb::io::File& file, const std::string& path, std::size_t l) {
    const std::string name = lamp_field_grid(l);
    vdb::GridBase::Ptr base;
    try {
        if (!file.hasGrid(name)) throw AssetError("multiple-scattering asset without grid " + name);
        base = file.readGrid(name);
    } catch (const AssetError& e) {
        throw AssetError(path + ": " + one_line(e.what()));
    } catch (const std::exception& e) {
        throw AssetError(path + ": truncated or damaged asset (" + one_line(e.what()) + ")");
    }
    const auto grid = vdb::gridPtrCast<vdb::Vec3SGrid>(base);
    LampField f;
    std::int32_t nr = 0, nt = 0;
    std::string sum;
    if (!grid || !get_meta(*grid, "deepsea:nr", nr) || !get_meta(*grid, "deepsea:ntheta", nt) ||
        !get_meta(*grid, kMetaFieldR0, f.r0) || !get_meta(*grid, kMetaFieldRMax, f.r_max) ||
        !get_meta(*grid, kMetaChecksum, sum) || nr < 2 || nt < 2 || nr > 4096 || nt > 4096 ||
        !(f.r0 > 0.0) || !(f.r_max > f.r0)) {
        throw AssetError(path + ": grid " + name + " is not a deepsea lamp field");
    }
    get_meta(*grid, kMetaFieldError, f.rel_std_error);
    f.nr = nr;
    f.ntheta = nt;
    const vdb::CoordBBox box(vdb::Coord(0, 0, 0), vdb::Coord(nr - 1, nt - 1, kShCount - 1));
    const vdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
    if (!active.empty() && !box.isInside(active)) {
        throw AssetError(path + ": grid " + name + " is larger than its table");
    }
    std::vector<vdb::Vec3s> dense_data(box.volume());
    vdb::tools::Dense<vdb::Vec3s, vdb::tools::LayoutZYX> dense(box, dense_data.data());
    vdb::tools::copyToDense(*grid, dense);
    f.sh.resize(dense_data.size() * 3);
    for (std::size_t n = 0; n < dense_data.size(); ++n) {
        for (int c = 0; c < 3; ++c) f.sh[3 * n + c] = dense_data[n][c];
    }
    if (hex(checksum(f.sh.data(), f.sh.size())) != sum) {
        throw AssetError(path + ": truncated or damaged asset (grid " + name +
                         " checksum mismatch)");
    }
    for (float x : f.sh) {
        if (!std::isfinite(x)) throw AssetError(path + ": non-finite value in grid " + name);
    }
    return f;
}

}  // namespace

Asset load_asset(const std::string& path) {
    OpenAsset f(path);
    Asset asset;
    asset.info = f.info;
    const Lattice& l = asset.info.lattice;
    vdb::GridBase::Ptr base;
    try {
        const char* grid = backscatter_grid_name(f.file);
        if (!f.file.hasGrid(grid)) throw AssetError("no backscatter grid");
        base = f.file.readGrid(grid);
    } catch (const AssetError& e) {
        throw AssetError(path + ": " + one_line(e.what()));
    } catch (const std::exception& e) {
        throw AssetError(path + ": truncated or damaged asset (" + one_line(e.what()) + ")");
    }
    const auto grid = vdb::gridPtrCast<vdb::Vec3SGrid>(base);
    if (!grid)
        throw AssetError(path + ": the backscatter grid is " + base->valueType() + ", not Vec3f");
    const vdb::CoordBBox box(vdb::Coord(0, 0, 0), vdb::Coord(l.ni - 1, l.nj - 1, l.nk() - 1));
    const vdb::CoordBBox active = grid->evalActiveVoxelBoundingBox();
    if (!active.empty() && !box.isInside(active)) {
        throw AssetError(path + ": backscatter grid is larger than its deepsea:bake lattice");
    }
    std::vector<vdb::Vec3s> dense_data(box.volume());
    {
        vdb::tools::Dense<vdb::Vec3s, vdb::tools::LayoutZYX> dense(box, dense_data.data());
        vdb::tools::copyToDense(*grid, dense);
    }
    std::string expect;
    if (get_meta(f.meta, kMetaChecksum, expect) &&
        hex(checksum(&dense_data[0][0], dense_data.size() * 3)) != expect) {
        throw AssetError(path + ": truncated or damaged asset (checksum mismatch)");
    }
    asset.values.resize(dense_data.size() * 3);
    const double inv = 1.0 / f.value_scale;
    for (std::size_t n = 0; n < dense_data.size(); ++n) {
        for (int c = 0; c < 3; ++c) {
            const float x = dense_data[n][c];
            if (!std::isfinite(x)) throw AssetError(path + ": non-finite backscatter value");
            asset.values[3 * n + c] = float(x * inv);
        }
    }
    std::string psf;
    if (get_meta(f.meta, kMetaForwardPsf, psf)) {
        try {
            asset.forward_psf = forward_psf_from_json(psf);
        } catch (const AssetError& e) {
            throw AssetError(path + ": " + one_line(e.what()));
        }
    }
    if (asset.info.scattering == Scattering::Multiple) {
        for (std::size_t l = 0; l < asset.info.rig.lights.size(); ++l) {
            asset.lamp_fields.push_back(lamp_field_from_file(f.file, path, l));
        }
    }
    return asset;
}

AssetFileSummary read_asset_summary(const std::string& path) {
    OpenAsset f(path);
    AssetFileSummary s;
    std::error_code ec;
    s.file_bytes = fs::file_size(path, ec);
    s.format = f.format;
    s.info = f.info;
    s.value_scale = f.value_scale;
    s.sha256 = f.record.sha256;
    get_meta(f.meta, kMetaPreviewVoxel, s.preview_voxel_size);
    get_meta(f.meta, kMetaPreviewScale, s.preview_density_scale);
    try {
        const auto grids = f.file.readAllGridMetadata();
        for (const auto& g : *grids) s.grids.push_back(summarize(*g));
        // OpenVDB lists grids by name; show the asset's own grid first.
        std::stable_partition(s.grids.begin(), s.grids.end(), [](const GridSummary& g) {
            return g.name == kBackscatterGrid || g.name == kOldBackscatterGrid;
        });
    } catch (const std::exception& e) {
        throw AssetError(path + ": damaged OpenVDB file (" + one_line(e.what()) + ")");
    }
    return s;
}

bool asset_up_to_date(const std::string& path, const std::string& input_hash) {
    std::error_code ec;
    if (!fs::exists(path, ec)) return false;
    try {
        const AssetFileSummary s = read_asset_summary(path);
        return s.format == kAssetFormat && s.info.input_hash == input_hash;
    } catch (const Error&) {
        return false;  // unreadable: bake it again
    }
}

std::vector<Vec3> index_to_world(const std::string& path, const std::string& grid,
                                 const std::vector<Vec3>& index_points) {
    OpenAsset f(path);
    vdb::GridBase::Ptr g;
    try {
        if (!f.file.hasGrid(grid)) throw AssetError(path + ": no grid named " + grid);
        g = f.file.readGridMetadata(grid);
    } catch (const AssetError&) {
        throw;
    } catch (const std::exception& e) {
        throw AssetError(path + ": damaged OpenVDB file (" + one_line(e.what()) + ")");
    }
    std::vector<Vec3> out;
    for (const Vec3& p : index_points) {
        const vdb::Vec3d w = g->transform().indexToWorld(vdb::Vec3d(p.x, p.y, p.z));
        out.push_back({w.x(), w.y(), w.z()});
    }
    return out;
}

}  // namespace deepsea
