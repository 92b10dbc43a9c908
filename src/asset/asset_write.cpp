// Writing the asset's file: the grids, their transforms and metadata, sealed and checked on
// the way to the disk (reading it back is asset_file.cpp).

#include <openvdb/io/File.h>
#include <openvdb/math/Transform.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "asset_vdb.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_integrity.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "forward_psf_json.h"
#include "preview.h"

namespace deepsea {

namespace fs = std::filesystem;
namespace vdb = openvdb;
using namespace asset_vdb;

namespace {

/// Power of two that puts the largest value near 2^12, so that half floats keep 11 bits for
/// everything down to 2^-26 of the maximum (half's normal range is 2^-14 .. 65504).
double half_scale(const std::vector<float>& v) {
    float m = 0.0f;
    for (float x : v) m = std::max(m, std::abs(x));
    if (!(m > 0.0f) || !std::isfinite(m)) return 1.0;
    return std::ldexp(1.0, 12 - std::ilogb(m) - 1);
}

/// Index cells 0 .. leaf_cells(n) - 1 that OpenVDB's leaf nodes (8^3 voxels) around index
/// 0 .. n - 1 span: Blender frames a grid by its leaf nodes, not by its active voxels.
int leaf_cells(int n) { return (n + 7) / 8 * 8; }

/// A diagonal affine transform: world = origin + scale * index, per axis. OpenVDB refuses a map
/// whose determinant is below about 3e-15 (cells of 14 micrometres) with an ArithmeticError
/// ("Tried to initialize an affine transform from a nearly singular matrix"): that becomes an
/// AssetError naming the cells, never a raw library message.
vdb::math::Transform::Ptr axis_transform(const Vec3& scale, const Vec3& origin) {
    const vdb::math::Mat4d m(scale.x, 0.0, 0.0, 0.0,  //
                             0.0, scale.y, 0.0, 0.0,  //
                             0.0, 0.0, scale.z, 0.0,  //
                             origin.x, origin.y, origin.z, 1.0);
    try {
        return vdb::math::Transform::createLinearTransform(m);
    } catch (const vdb::Exception&) {
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "cells of %.3g x %.3g x %.3g m are too small for an OpenVDB transform",
                      std::fabs(scale.x), std::fabs(scale.y), std::fabs(scale.z));
        throw AssetError(buf);
    }
}

/// The depth (metres) of the view extent every grid is placed in: the lamps' beams (the preview
/// domain's depth, at least 1 m), at most z_max. So Frame All in Blender frames the beams.
double view_depth(const Rig& rig, const Water& water, const Camera& cam, double z_max) {
    const WorldBox beams = detail::beam_domain(rig, water, frustum_extent(cam, z_max));
    const double d = beams.min.z < beams.max.z ? -beams.min.z : z_max;
    return std::min(z_max, std::max(d, 1.0));
}

/// The backscatter grid's transform (every depth scheme): its index box, rounded up to whole
/// leaf nodes, divided evenly over the frustum's bounding box to the view depth, index (i, j, k) at
/// the centre of cell (i, j, k); columns left to right, rows top to bottom, samples from the camera
/// forward. So a plain import frames the light field. The true camera-space point of a
/// voxel is in the grid's metadata (add_lattice_geometry_meta), not in this map: OpenVDB's frustum
/// map holds only uniform depths, and Blender 3.4 drops its perspective (docs/blender.md).
vdb::math::Transform::Ptr lattice_transform(const Camera& cam, const Lattice& l, double depth) {
    const WorldBox box = frustum_extent(cam, depth);
    const Vec3 cell{(box.max.x - box.min.x) / leaf_cells(l.ni),
                    (box.max.y - box.min.y) / leaf_cells(l.nj),
                    (box.max.z - box.min.z) / leaf_cells(l.nk())};
    return axis_transform(
        {cell.x, -cell.y, -cell.z},
        {box.min.x + 0.5 * cell.x, box.max.y - 0.5 * cell.y, box.max.z - 0.5 * cell.z});
}

/// Grid metadata from which a tool that knows nothing of deepsea (Houdini, pyopenvdb) gets
/// the camera-space point of backscatter voxel (i, j, k) in every depth scheme
/// (docs/asset-format.md, "The backscatter grid's transform and its camera-space geometry").
void add_lattice_geometry_meta(vdb::GridBase& grid, const Camera& cam, const Lattice& l) {
    grid.insertMeta("deepsea:index_to_camera",
                    vdb::StringMetadata("OpenCV camera point of index (i, j, k): z = "
                                        "z_samples[k], x = (i * step - cx) / fx * z, y = "
                                        "(j * step - cy) / fy * z; world = (x, -y, -z)"));
    grid.insertMeta("deepsea:step", vdb::Int32Metadata(l.step));
    grid.insertMeta("deepsea:fx", vdb::DoubleMetadata(cam.fx));
    grid.insertMeta("deepsea:fy", vdb::DoubleMetadata(cam.fy));
    grid.insertMeta("deepsea:cx", vdb::DoubleMetadata(cam.cx));
    grid.insertMeta("deepsea:cy", vdb::DoubleMetadata(cam.cy));
    grid.insertMeta("deepsea:depth_scheme", vdb::StringMetadata(to_string(l.scheme)));
}

/// A lamp field's transform: cubic voxels of at most 1 mm, the table's leaf box centred in the
/// frustum's bounding box (its index space is not space; it only has to stay out of the way).
vdb::math::Transform::Ptr lamp_field_transform(const LampField& f, const WorldBox& box) {
    const int n[3] = {leaf_cells(f.nr), leaf_cells(f.ntheta), leaf_cells(kShCount)};
    double h = 1e-3;
    for (int a = 0; a < 3; ++a) h = std::min(h, 0.5 * (box.max[a] - box.min[a]) / n[a]);
    const auto start = [&](int a) {
        return 0.5 * (box.min[a] + box.max[a]) - 0.5 * h * (n[a] - 1);
    };
    return axis_transform({h, h, h}, {start(0), start(1), start(2)});
}

/// OpenVDB's archive writer, made to write into memory: io::File writes to a path and does not
/// check the stream, so a full disk used to leave a short file and no error. In memory the
/// bytes are complete, are sealed with their integrity record, and are then written and read
/// back with every step checked.
class MemoryArchive : public vdb::io::Archive {
public:
    std::string bytes(const vdb::GridPtrVec& grids, const vdb::MetaMap& meta) const {
        std::ostringstream os(std::ios::binary);
        Archive::write(os, grids, /*seekable=*/true, meta);
        if (!os) throw AssetError("OpenVDB could not serialise the asset");
        return std::move(os).str();
    }
};

/// A lamp field as a Vec3f grid, index (i, j, m) = (distance, angle, SH coefficient), RGB per
/// voxel, full float. Its small voxels keep it inside the frustum's box in world space (a grid
/// of unit voxels would frame a box metres wide around nothing in Blender).
vdb::GridBase::Ptr lamp_field_to_grid(const LampField& f, std::size_t l, const WorldBox& extent) {
    std::vector<vdb::Vec3s> stored(f.sh.size() / 3);
    for (std::size_t n = 0; n < stored.size(); ++n) {
        stored[n] = vdb::Vec3s(f.sh[3 * n], f.sh[3 * n + 1], f.sh[3 * n + 2]);
    }
    const vdb::CoordBBox box(vdb::Coord(0, 0, 0), vdb::Coord(f.nr - 1, f.ntheta - 1, kShCount - 1));
    auto grid = vdb::Vec3SGrid::create(vdb::Vec3s(0.0f));
    // Layout: (i, j, m) with m fastest, as LampField::sh: OpenVDB's z-y-x dense layout.
    vdb::tools::Dense<vdb::Vec3s, vdb::tools::LayoutZYX> dense(box, stored.data());
    vdb::tools::copyFromDense(dense, *grid, vdb::Vec3s(0.0f));
    grid->setName(lamp_field_grid(l));
    grid->setTransform(lamp_field_transform(f, extent));
    grid->setVectorType(vdb::VEC_INVARIANT);
    grid->insertMeta(kMetaFieldR0, vdb::DoubleMetadata(f.r0));
    grid->insertMeta(kMetaFieldRMax, vdb::DoubleMetadata(f.r_max));
    grid->insertMeta(kMetaFieldError, vdb::DoubleMetadata(f.rel_std_error));
    grid->insertMeta("deepsea:nr", vdb::Int32Metadata(f.nr));
    grid->insertMeta("deepsea:ntheta", vdb::Int32Metadata(f.ntheta));
    grid->insertMeta(kMetaChecksum, vdb::StringMetadata(hex(checksum(f.sh.data(), f.sh.size()))));
    return grid;
}

}  // namespace

void require_writable(const std::string& path) {
    if (fs::path(path).filename().empty())
        throw IoError("cannot write " + path + ": not a file name");
    std::string ext = fs::path(path).extension().string();
    for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (ext != ".vdb") {
        throw IoError("cannot write " + path + ": an asset is an OpenVDB file, its name must end " +
                      "in .vdb");
    }
    require_writable_folder(path);
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw IoError("cannot write " + path + ": it is a directory");
}

void check_storable(const Camera& camera, const Lattice& lattice) {
    init_openvdb();
    try {
        lattice_transform(camera, lattice, std::min(lattice.z_max(), 1.0));
        LampField f;
        const LampFieldSettings ls;
        f.nr = ls.nr;
        f.ntheta = ls.ntheta;
        lamp_field_transform(f, frustum_extent(camera, std::min(lattice.z_max(), 1.0)));
    } catch (const AssetError& e) {
        char z[32];
        std::snprintf(z, sizeof z, "%g", lattice.z_max());
        throw ConfigError("the lattice cannot be stored (z_max " + std::string(z) + " m, " +
                          std::to_string(lattice.ni) + " x " + std::to_string(lattice.nj) +
                          " columns x " + std::to_string(lattice.nk()) + " samples): " + e.what() +
                          "; give a larger z_max or xy_step or fewer depth samples");
    }
}

void write_asset(const std::string& path, const Asset& asset, const WriteOptions& opt) {
    const Lattice& l = asset.lattice();
    if (l.ni < 1 || l.nj < 1 || l.nk() < 2) throw AssetError("write_asset: empty lattice");
    if (asset.values.size() != std::size_t(l.ni) * l.nj * l.nk() * 3) {
        throw AssetError("write_asset: " + std::to_string(asset.values.size()) +
                         " values do not fill the lattice");
    }
    require_writable(path);  // fail before the work of building the grids
    init_openvdb();

    // The stored values: optionally scaled by a power of two (exact) and rounded to half, so
    // that the checksum is of exactly what the loader will see.
    const double scale = opt.half ? half_scale(asset.values) : 1.0;
    std::vector<vdb::Vec3s> stored(asset.values.size() / 3);
    for (std::size_t n = 0; n < stored.size(); ++n) {
        for (int c = 0; c < 3; ++c) {
            float x = float(asset.values[3 * n + c] * scale);
            if (opt.half) x = float(vdb::math::half(x));
            stored[n][c] = x;
        }
    }
    const std::uint64_t sum = checksum(&stored[0][0], stored.size() * 3);

    const vdb::CoordBBox box(vdb::Coord(0, 0, 0), vdb::Coord(l.ni - 1, l.nj - 1, l.nk() - 1));
    auto grid = vdb::Vec3SGrid::create(vdb::Vec3s(0.0f));
    {
        vdb::tools::Dense<vdb::Vec3s, vdb::tools::LayoutZYX> dense(box, stored.data());
        vdb::tools::copyFromDense(dense, *grid, vdb::Vec3s(0.0f));
    }
    // The beams decide where every grid goes: a plain import frames them (docs/blender.md).
    const detail::Preview preview =
        opt.preview ? detail::make_preview(asset, std::max(opt.preview_resolution, 8))
                    : detail::Preview{};
    const double z_view =
        view_depth(asset.info.rig, asset.info.water, asset.info.camera, l.z_max());
    grid->setName(kBackscatterGrid);
    grid->setTransform(lattice_transform(asset.info.camera, l, z_view));
    add_lattice_geometry_meta(*grid, asset.info.camera, l);
    const WorldBox extent = frustum_extent(asset.info.camera, z_view);
    grid->setSaveFloatAsHalf(opt.half);
    grid->setVectorType(vdb::VEC_INVARIANT);

    vdb::MetaMap meta;
    meta.insertMeta(kMetaFormat, vdb::Int32Metadata(kAssetFormat));
    meta.insertMeta(kMetaBake, vdb::StringMetadata(bake_info_to_json(asset.info)));
    meta.insertMeta(kMetaScale, vdb::DoubleMetadata(scale));
    meta.insertMeta(kMetaChecksum, vdb::StringMetadata(hex(sum)));
    std::string zs;
    for (double z : l.z) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%s%.17g", zs.empty() ? "" : " ", z);
        zs += buf;
    }
    meta.insertMeta(kMetaZ, vdb::StringMetadata(zs));
    for (auto it = meta.beginMeta(); it != meta.endMeta(); ++it)
        grid->insertMeta(it->first, *it->second);

    // The backscatter grid goes last: a truncated file then always damages it (or the
    // descriptors before it), and load_asset, which reads only this grid, notices.
    vdb::GridPtrVec grids;
    if (opt.preview && !preview.voxels.empty()) {
        auto density = vdb::FloatGrid::create(0.0f);
        auto da = density->getAccessor();
        for (const auto& v : preview.voxels) da.setValue(vdb::Coord(v.a, v.b, v.c), v.density);
        vdb::math::Transform::Ptr xform;
        try {
            xform = vdb::math::Transform::createLinearTransform(preview.voxel_size);
        } catch (const vdb::Exception&) {
            throw AssetError("cannot write " + path + ": preview voxels of " +
                             std::to_string(preview.voxel_size) +
                             " m are too small for an OpenVDB transform");
        }
        density->setTransform(xform);
        density->setName(kDensityGrid);
        density->setGridClass(vdb::GRID_FOG_VOLUME);
        density->setSaveFloatAsHalf(true);
        grids.push_back(density);
        meta.insertMeta(kMetaPreviewVoxel, vdb::DoubleMetadata(preview.voxel_size));
        meta.insertMeta(kMetaPreviewScale, vdb::DoubleMetadata(preview.density_scale));
    }
    if (asset.info.scattering == Scattering::Multiple) {
        if (asset.lamp_fields.size() != asset.info.rig.lights.size()) {
            throw AssetError(
                "write_asset: a multiple-scattering asset needs one lamp field per lamp");
        }
        for (std::size_t l = 0; l < asset.lamp_fields.size(); ++l) {
            grids.push_back(lamp_field_to_grid(asset.lamp_fields[l], l, extent));
        }
    }
    grids.push_back(grid);
    if (asset.forward_psf) {
        asset.forward_psf->validate("write_asset: forward scatter table");
        meta.insertMeta(kMetaForwardPsf,
                        vdb::StringMetadata(forward_psf_to_json(*asset.forward_psf)));
    }
    meta.insertMeta("creator", vdb::StringMetadata("deepsea bake"));
    meta.insertMeta(kMetaIntegrity, vdb::StringMetadata(integrity_placeholder()));

    MemoryArchive archive;
    archive.setCompression(vdb::io::Archive::hasBloscCompression()
                               ? vdb::io::COMPRESS_BLOSC | vdb::io::COMPRESS_ACTIVE_MASK
                               : vdb::io::COMPRESS_ZIP | vdb::io::COMPRESS_ACTIVE_MASK);
    std::string bytes;
    try {
        bytes = archive.bytes(grids, meta);
    } catch (const AssetError&) {
        throw;
    } catch (const std::exception& e) {
        throw AssetError("cannot serialise asset " + path + ": " + one_line(e.what()));
    }
    const IntegrityRecord sealed = seal_asset_bytes(bytes);

    // A missing folder or a failed rename is reported by write_atomically, naming the path.
    // What reaches the disk is read back and compared before the rename: a full disk, or a
    // device that loses a write, is an error and leaves no file.
    write_atomically(path, [&](const std::string& tmp) {
        write_fully(tmp, bytes, path);
        IntegrityRecord back;
        try {
            back = verify_asset_file(tmp);
        } catch (const Error& e) {
            throw IoError(path + ": the file read back is not the one written (" +
                          one_line(e.what()) + ")");
        }
        if (back.size != sealed.size || back.sha256 != sealed.sha256)
            throw IoError(path + ": the file read back is not the one written");
    });
}

}  // namespace deepsea
