#include "deepsea/asset/asset_file.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "../message_of.h"
#include "../temp_folder.h"
#include "deepsea/asset/asset_integrity.h"
#include "deepsea/core/error.h"
#include "test_assets.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

const Camera kCam{64, 48, 50.0, 52.0, 31.5, 23.0};  // off-centre principal point, fx != fy

class AssetFile : public test::TempFolderTest {
protected:
    std::vector<char> read_bytes(const std::string& p) const {
        std::ifstream f(p, std::ios::binary);
        return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
    }
    void write_bytes(const std::string& p, const std::vector<char>& b, std::size_t n) const {
        std::ofstream f(p, std::ios::binary);
        f.write(b.data(), std::streamsize(n));
    }
    /// Writes edited bytes with a fresh integrity record: what the edit broke, not the hash,
    /// must then be what the loader refuses.
    void write_sealed(const std::string& p, const std::vector<char>& b) const {
        std::string s(b.begin(), b.end());
        seal_asset_bytes(s);
        write_bytes(p, std::vector<char>(s.begin(), s.end()), s.size());
    }
    bool has_temp_files() const {
        for (const auto& e : fs::directory_iterator(dir_)) {
            if (e.path().filename().string().find(".tmp") != std::string::npos) return true;
        }
        return false;
    }
};

Asset smooth_asset(DepthScheme scheme = DepthScheme::Uniform) {
    return test::function_asset(kCam, 8, scheme, 10, 5.0, test::smooth_field);
}

TEST_F(AssetFile, RoundTripFloatIsExact) {
    const Asset a = smooth_asset();
    WriteOptions opt;
    opt.half = false;
    write_asset(path("a.vdb"), a, opt);
    EXPECT_FALSE(has_temp_files());
    const Asset b = load_asset(path("a.vdb"));
    ASSERT_EQ(b.values.size(), a.values.size());
    EXPECT_EQ(std::memcmp(b.values.data(), a.values.data(), a.values.size() * sizeof(float)), 0);
    EXPECT_TRUE(b.info.camera == a.info.camera);
    EXPECT_TRUE(b.info.lattice == a.info.lattice);
    EXPECT_EQ(b.info.rig.lights.size(), 2u);
    EXPECT_EQ(b.info.water.c.g, a.info.water.c.g);
    EXPECT_EQ(b.info.input_hash, a.info.input_hash);
}

TEST_F(AssetFile, ForwardScatterTableRoundTripsExactly) {
    Asset a = smooth_asset();
    write_asset(path("none.vdb"), a);
    EXPECT_FALSE(load_asset(path("none.vdb")).forward_psf);  // as assets before the table
    ForwardTransportSettings fs;
    fs.paths = 256;
    fs.rings = 8;
    a.forward_psf = trace_forward_psf(a.info.water, {0.5, 1.5, 4.0}, fs);
    write_asset(path("t.vdb"), a);
    const Asset b = load_asset(path("t.vdb"));
    ASSERT_TRUE(b.forward_psf);
    EXPECT_EQ(b.forward_psf->depth, a.forward_psf->depth);
    EXPECT_EQ(b.forward_psf->ring_edge, a.forward_psf->ring_edge);
    ASSERT_EQ(b.forward_psf->share.size(), a.forward_psf->share.size());
    for (std::size_t i = 0; i < a.forward_psf->share.size(); ++i)
        EXPECT_EQ(b.forward_psf->share[i].g, a.forward_psf->share[i].g);
    EXPECT_EQ(b.forward_psf->std_error[2].b, a.forward_psf->std_error[2].b);
    EXPECT_EQ(b.forward_psf->paths, 256);
    // a malformed table is refused when written, naming it, and nothing is left behind
    a.forward_psf->share.pop_back();
    EXPECT_THROW(write_asset(path("bad.vdb"), a), ConfigError);
    EXPECT_FALSE(fs::exists(path("bad.vdb")));
}

TEST_F(AssetFile, RoundTripHalfKeepsElevenBits) {
    const Asset a = smooth_asset();
    write_asset(path("a.vdb"), a);  // half is the default
    const Asset b = load_asset(path("a.vdb"));
    ASSERT_EQ(b.values.size(), a.values.size());
    for (std::size_t n = 0; n < a.values.size(); ++n) {
        ASSERT_NEAR(b.values[n], a.values[n], std::ldexp(std::abs(a.values[n]), -11)) << n;
    }
    const AssetFileSummary s = read_asset_summary(path("a.vdb"));
    ASSERT_FALSE(s.grids.empty());
    EXPECT_EQ(s.grids[0].name, kBackscatterGrid);
    EXPECT_TRUE(s.grids[0].half);
    EXPECT_EQ(s.format, kAssetFormat);
    EXPECT_GT(s.file_bytes, 0u);
}

/// Every grid of the file, leaf nodes included (what Blender frames), lies in the frustum's
/// extent and spans a good part of it.
void expect_in_extent(const AssetFileSummary& s, const Camera& cam, double z_max) {
    const WorldBox box = frustum_extent(cam, z_max);
    for (const GridSummary& g : s.grids) {
        SCOPED_TRACE(g.name);
        EXPECT_GT(g.active_voxels, 0);
        for (int a = 0; a < 3; ++a) {
            const double size = box.max[a] - box.min[a], tol = 1e-9 * size;
            EXPECT_GE(g.leaf_world_min[a], box.min[a] - tol) << "axis " << a;
            EXPECT_LE(g.leaf_world_max[a], box.max[a] + tol) << "axis " << a;
            EXPECT_LE(g.leaf_world_min[a], g.world_min[a]) << "axis " << a;
            EXPECT_GE(g.leaf_world_max[a], g.world_max[a]) << "axis " << a;
            EXPECT_LT(g.world_min[a], g.world_max[a]) << "axis " << a;  // not flat
        }
    }
}

TEST_F(AssetFile, EveryGridLiesInTheFrustumExtentInEveryDepthScheme) {
    const Camera wide{96, 72, 33.61, 33.61, 47.5, 35.5};  // 110 degrees
    for (const Camera& cam : {kCam, wide, Camera{800, 800, 600, 600, 400, 400}}) {
        for (DepthScheme scheme :
             {DepthScheme::Uniform, DepthScheme::Taylor, DepthScheme::Sqrt, DepthScheme::Log}) {
            SCOPED_TRACE(describe(cam) + " " + to_string(scheme));
            const Asset a = test::function_asset(cam, 8, scheme, 10, 5.0, test::smooth_field);
            write_asset(path("e.vdb"), a);
            const AssetFileSummary s = read_asset_summary(path("e.vdb"));
            ASSERT_EQ(s.grids.size(), 2u);
            EXPECT_EQ(s.grids.at(0).name, kBackscatterGrid);
            EXPECT_EQ(s.grids.at(0).transform, "linear");
            expect_in_extent(s, cam, 5.0);
        }
    }
}

TEST_F(AssetFile, LampFieldsLieInTheFrustumExtent) {
    Asset a = smooth_asset(DepthScheme::Log);
    a.info.scattering = Scattering::Multiple;
    for (std::size_t l = 0; l < a.info.rig.lights.size(); ++l) {
        LampField f;
        f.nr = 40;
        f.ntheta = 37;
        f.r0 = 0.02;
        f.r_max = 30.0;
        f.sh.assign(f.size(), 0.5f);
        a.lamp_fields.push_back(f);
    }
    write_asset(path("m.vdb"), a);
    const AssetFileSummary s = read_asset_summary(path("m.vdb"));
    ASSERT_EQ(s.grids.size(), 4u);
    expect_in_extent(s, kCam, 5.0);
    EXPECT_EQ(load_asset(path("m.vdb")).lamp_fields.at(1).sh, a.lamp_fields[1].sh);
}

TEST_F(AssetFile, BackscatterTransformKeepsTheCameraOrientation) {
    // Columns left to right, rows top to bottom (world y is up), samples from the camera on.
    const Asset a = smooth_asset(DepthScheme::Log);
    write_asset(path("o.vdb"), a);
    const Lattice& l = a.lattice();
    const std::vector<Vec3> w = index_to_world(
        path("o.vdb"), kBackscatterGrid,
        {{0, 0, 0}, {double(l.ni - 1), 0, 0}, {0, double(l.nj - 1), 0}, {0, 0, double(l.slabs())}});
    EXPECT_LT(w[0].x, w[1].x);
    EXPECT_GT(w[0].y, w[2].y);
    EXPECT_GT(w[0].z, w[3].z);
    EXPECT_LT(w[0].z, 0.0);
}

TEST_F(AssetFile, NonUniformSamplesKeepTheirDepths) {
    const Asset a = smooth_asset(DepthScheme::Log);
    write_asset(path("l.vdb"), a);
    const Asset b = load_asset(path("l.vdb"));
    EXPECT_EQ(b.lattice().scheme, DepthScheme::Log);
    EXPECT_EQ(b.lattice().z, a.lattice().z);
}

TEST_F(AssetFile, TheTransformDoesNotChangeTheValues) {
    // The loader reads by index: the same values in every scheme, whatever the transform.
    for (DepthScheme scheme : {DepthScheme::Uniform, DepthScheme::Log}) {
        const Asset a = smooth_asset(scheme);
        WriteOptions opt;
        opt.half = false;
        write_asset(path("v.vdb"), a, opt);
        const Asset b = load_asset(path("v.vdb"));
        ASSERT_EQ(b.values.size(), a.values.size());
        EXPECT_EQ(std::memcmp(b.values.data(), a.values.data(), a.values.size() * sizeof(float)),
                  0);
    }
}

TEST_F(AssetFile, PreviewGridsLieInTheFrustum) {
    const Asset a = smooth_asset();
    write_asset(path("p.vdb"), a);
    const AssetFileSummary s = read_asset_summary(path("p.vdb"));
    ASSERT_EQ(s.grids.size(), 2u);
    EXPECT_EQ(s.grids[0].name, kBackscatterGrid);
    const auto find = [&](const char* name) {
        for (const GridSummary& g : s.grids) {
            if (g.name == name) return g;
        }
        ADD_FAILURE() << "no grid " << name;
        return GridSummary{};
    };
    EXPECT_EQ(find(kDensityGrid).value_type, "float");
    EXPECT_GT(s.preview_voxel_size, 0.0);
    EXPECT_GT(s.preview_density_scale, 0.0);
    for (const char* name : {kDensityGrid}) {
        const GridSummary p = find(name);
        EXPECT_EQ(p.transform, "linear");
        EXPECT_GT(p.active_voxels, 0);
    }
    expect_in_extent(s, kCam, 5.0);
}

TEST_F(AssetFile, EveryGridLiesWithinTheBeamsDepth) {
    // What Blender's Frame All frames (the union of every grid's leaf nodes) reaches no deeper
    // than the beams (the density grid), or 1 m, so the beams fill the view: the backscatter
    // grid's box used to reach z_max (a 35 m box around cones a few metres long).
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Log, 10, 40.0, test::smooth_field);
    write_asset(path("b.vdb"), a);
    const AssetFileSummary s = read_asset_summary(path("b.vdb"));
    double beams = 0.0, deepest = 0.0;
    for (const GridSummary& g : s.grids) {
        if (g.name == kDensityGrid) beams = -g.leaf_world_min.z;
        deepest = std::max(deepest, -g.leaf_world_min.z);
    }
    ASSERT_GT(beams, 1.0);
    EXPECT_LT(beams, 20.0);
    // the beams' box, less the leaf nodes that would reach out of it
    EXPECT_LE(deepest, beams + 8 * s.preview_voxel_size + 1e-9);
}

TEST_F(AssetFile, MissingFileIsIoError) { EXPECT_THROW(load_asset(path("none.vdb")), IoError); }

TEST_F(AssetFile, ForeignFileIsAssetError) {
    std::ofstream(path("text.vdb")) << "this is not a vdb file\n";
    EXPECT_THROW(load_asset(path("text.vdb")), AssetError);
    EXPECT_THROW(read_asset_summary(path("text.vdb")), AssetError);
    write_bytes(path("empty.vdb"), {}, 0);
    EXPECT_THROW(load_asset(path("empty.vdb")), AssetError);
}

TEST_F(AssetFile, TruncatedFileIsAssetError) {
    for (bool half : {true, false}) {
        WriteOptions opt;
        opt.half = half;
        write_asset(path("a.vdb"), smooth_asset(), opt);
        const std::vector<char> bytes = read_bytes(path("a.vdb"));
        ASSERT_GT(bytes.size(), 100u);
        for (double f : {0.02, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
            write_bytes(path("t.vdb"), bytes, std::size_t(f * bytes.size()));
            EXPECT_THROW(load_asset(path("t.vdb")), AssetError) << f << " half " << half;
        }
        write_bytes(path("t.vdb"), bytes, bytes.size() - 1);
        EXPECT_THROW(load_asset(path("t.vdb")), AssetError) << "one byte short, half " << half;
    }
}

/// Rewrites the int32 value of every `deepsea:format` metadata entry (file and grid) in place:
/// name, then type name "int32" (length-prefixed), then the value size 4 and the value.
int patch_format(std::vector<char>& bytes, std::int32_t value) {
    const std::string key = "deepsea:format";
    int patched = 0;
    for (std::size_t pos = 0; pos + key.size() + 17 < bytes.size(); ++pos) {
        if (std::memcmp(&bytes[pos], key.data(), key.size()) != 0) continue;
        const std::size_t type = pos + key.size();
        if (std::memcmp(&bytes[type + 4], "int32", 5) != 0) continue;
        std::memcpy(&bytes[type + 4 + 5 + 4], &value, 4);
        ++patched;
    }
    return patched;
}

TEST_F(AssetFile, NewerFormatIsAssetError) {
    write_asset(path("a.vdb"), smooth_asset());
    std::vector<char> bytes = read_bytes(path("a.vdb"));
    std::vector<char> same = bytes;
    ASSERT_EQ(patch_format(same, kAssetFormat), 2);  // file and grid metadata
    write_sealed(path("same.vdb"), same);
    EXPECT_NO_THROW(load_asset(path("same.vdb")));  // the patch itself is harmless
    patch_format(bytes, 999);
    write_sealed(path("new.vdb"), bytes);
    try {
        load_asset(path("new.vdb"));
        FAIL() << "no AssetError";
    } catch (const AssetError& e) {
        EXPECT_NE(std::string(e.what()).find("999"), std::string::npos) << e.what();
    }
}

TEST_F(AssetFile, VdbWithoutDeepseaMetadataIsAssetError) {
    write_asset(path("a.vdb"), smooth_asset());
    std::vector<char> bytes = read_bytes(path("a.vdb"));
    const std::string key = "deepsea:format";
    for (std::size_t pos = 0; pos + key.size() < bytes.size(); ++pos) {
        if (std::memcmp(&bytes[pos], key.data(), key.size()) == 0)
            bytes[pos + key.size() - 1] = 'X';
    }
    write_sealed(path("plain.vdb"), bytes);
    EXPECT_THROW(load_asset(path("plain.vdb")), AssetError);
}

/// The AssetError message of loading `p`, or "" when it loads.
std::string load_error(const std::string& p) {
    return test::message_of<AssetError>([&] { load_asset(p); });
}

TEST_F(AssetFile, EveryChangedByteIsRefusedBeforeOpenVdbParses) {
    // Every byte of a whole file, flipped one at a time: each is refused by the integrity
    // check with one line naming the file (before, some made OpenVDB's Blosc reader overflow
    // the heap or allocate gigabytes).
    WriteOptions opt;
    opt.preview = false;
    write_asset(path("a.vdb"), smooth_asset(), opt);
    const std::vector<char> good = read_bytes(path("a.vdb"));
    ASSERT_GT(good.size(), 1000u);
    int refused = 0;
    for (std::size_t i = 0; i < good.size(); ++i) {
        std::vector<char> bad = good;
        bad[i] = char(bad[i] ^ 0x01);
        // A new name each time: ext4 flushes a file truncated and rewritten in place on close.
        const std::string p = path("b" + std::to_string(i) + ".vdb");
        write_bytes(p, bad, bad.size());
        const std::string why = load_error(p);
        EXPECT_NE(why.find(p + ": "), std::string::npos) << "byte " << i << ": " << why;
        EXPECT_EQ(why.find('\n'), std::string::npos) << why;
        refused += !why.empty();
        fs::remove(p);
    }
    EXPECT_EQ(refused, int(good.size()));
}

TEST_F(AssetFile, IntegrityRecordCoversTheMetadata) {
    write_asset(path("a.vdb"), smooth_asset());
    std::vector<char> bytes = read_bytes(path("a.vdb"));
    const std::string key = "\"attenuation\":[";
    auto it = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    ASSERT_NE(it, bytes.end());
    it[key.size()] = '9';  // a plausible value, edited: only the hash notices
    write_bytes(path("e.vdb"), bytes, bytes.size());
    EXPECT_NE(load_error(path("e.vdb")).find("SHA-256"), std::string::npos);
    EXPECT_THROW(read_asset_summary(path("e.vdb")), AssetError);
}

TEST_F(AssetFile, AssetWithoutIntegrityRecordAsksForARebake) {
    write_asset(path("a.vdb"), smooth_asset());
    std::vector<char> bytes = read_bytes(path("a.vdb"));
    const std::string key = kMetaIntegrity;
    auto it = std::search(bytes.begin(), bytes.end(), key.begin(), key.end());
    ASSERT_NE(it, bytes.end());
    it[key.size() - 1] = 'X';  // as an older deepsea wrote it: no deepsea:integrity
    write_bytes(path("old.vdb"), bytes, bytes.size());
    EXPECT_NE(load_error(path("old.vdb")).find("re-bake"), std::string::npos);
}

TEST_F(AssetFile, SummaryReportsTheVerifiedHash) {
    write_asset(path("a.vdb"), smooth_asset());
    const AssetFileSummary s = read_asset_summary(path("a.vdb"));
    EXPECT_EQ(s.sha256.size(), 64u);
    EXPECT_EQ(s.sha256, verify_asset_file(path("a.vdb")).sha256);
    EXPECT_EQ(verify_asset_file(path("a.vdb")).size, fs::file_size(path("a.vdb")));
}

TEST_F(AssetFile, OtherExtensionsThanVdbAreRefused) {
    for (const char* name : {"a.exr", "a", "a.vdb.tmp"}) {
        EXPECT_THROW(require_writable(path(name)), IoError) << name;
        EXPECT_THROW(write_asset(path(name), smooth_asset()), IoError) << name;
        EXPECT_FALSE(fs::exists(path(name))) << name;
    }
    EXPECT_NO_THROW(require_writable(path("A.VDB")));
}

TEST_F(AssetFile, UnwritableTargetsAreIoErrorsAndLeaveNoFiles) {
    const Asset a = smooth_asset();
    EXPECT_THROW(write_asset(path("no/such/dir/a.vdb"), a), IoError);
    EXPECT_THROW(require_writable(path("no/such/dir/a.vdb")), IoError);
    // The target is a non-empty directory: the temporary file is written, the rename fails.
    fs::create_directories(dir_ / "busy.vdb" / "x");
    EXPECT_THROW(require_writable(path("busy.vdb")), IoError);
    EXPECT_THROW(write_asset(path("busy.vdb"), a), IoError);
    EXPECT_FALSE(has_temp_files());
}

TEST_F(AssetFile, InconsistentAssetIsRefused) {
    Asset a = smooth_asset();
    a.values.pop_back();
    EXPECT_THROW(write_asset(path("a.vdb"), a), AssetError);
    EXPECT_FALSE(fs::exists(path("a.vdb")));
    EXPECT_FALSE(has_temp_files());
}

TEST_F(AssetFile, OverwritesAnExistingAsset) {
    write_asset(path("a.vdb"), smooth_asset());
    const Asset b = smooth_asset(DepthScheme::Sqrt);
    write_asset(path("a.vdb"), b);
    EXPECT_EQ(load_asset(path("a.vdb")).lattice().scheme, DepthScheme::Sqrt);
    EXPECT_FALSE(has_temp_files());
}

}  // namespace
}  // namespace deepsea
