// The `density` preview: the lamps' beams around the rig (docs/asset-format.md, "Preview
// grid"), checked against the lamp equation written out here, and by where the beams point.
#include "preview.h"

#include <gtest/gtest.h>

#include <cmath>

#include "deepsea/asset/asset_file.h"
#include "test_assets.h"

namespace deepsea {
namespace {

const Camera kCam{800, 800, 600.0, 600.0, 399.5, 399.5};

Asset beams_asset(const Rig& rig) {
    Asset a = test::function_asset(kCam, 32, DepthScheme::Log, 16, 20.0,
                                   [](double, double, double z) { return Rgb(z); });
    a.info.rig = rig;
    return a;
}

/// DESIGN.md's lamp, independently: b I0 exp(-theta^2 / (2 sigma^2)) exp(-c d) / d^2, the
/// luminance of its sum over lamps (camera-frame point X).
double source(const Rig& rig, const Water& w, const Vec3& X) {
    double y = 0.0;
    for (const Light& L : rig.lights) {
        const Vec3 d = X - L.position;
        const double r = length(d);
        const double theta = std::acos(std::clamp(dot(d, L.direction) / r, -1.0, 1.0));
        const double sigma = L.rid.sigma_deg * M_PI / 180.0;
        const double g = std::exp(-theta * theta / (2.0 * sigma * sigma)) / (r * r);
        const double k[3] = {0.2126, 0.7152, 0.0722};
        for (int c = 0; c < 3; ++c) y += k[c] * w.b[c] * L.intensity[c] * g * std::exp(-w.c[c] * r);
    }
    return y;
}

TEST(Preview, DensityIsTheLampsSourceInDecadesBelowItsValueTenCentimetresDownTheAxis) {
    const Asset a = beams_asset(test::two_lamp_rig());
    const detail::Preview p = detail::make_preview(a, 64);
    ASSERT_GT(p.voxels.size(), 1000u);
    Rig one = a.info.rig;
    one.lights.resize(1);
    const Light& L = one.lights[0];
    const double scale = source(one, a.info.water, L.position + L.direction * 0.1);
    EXPECT_NEAR(p.density_scale, scale, 1e-9 * scale);
    const double h = p.voxel_size;
    for (std::size_t n = 0; n < p.voxels.size(); n += 37) {
        const detail::PreviewVoxel& v = p.voxels[n];
        // 1 + log10(S / S_ref) / 3, clamped to [0, 1]
        const double s = source(a.info.rig, a.info.water, {v.a * h, -v.b * h, -v.c * h});
        const double want = std::clamp(1.0 + std::log10(s / scale) / 3.0, 0.0, 1.0);
        ASSERT_NEAR(v.density, want, 1e-6) << v.a << " " << v.b << " " << v.c;
        ASSERT_GE(v.density, detail::kBeamCut);
    }
}

TEST(Preview, LeafNodesLieInTheDomainInFrontOfTheCamera) {
    const Asset a = beams_asset(test::two_lamp_rig());
    const detail::Preview p = detail::make_preview(a, 64);
    const WorldBox extent = frustum_extent(kCam, 20.0);
    const WorldBox& d = p.domain;
    EXPECT_LE(d.max.z, 0.0);
    for (int k = 0; k < 3; ++k) {
        EXPECT_GE(d.min[k], extent.min[k]);
        EXPECT_LE(d.max[k], extent.max[k]);
    }
    const double h = p.voxel_size, eps = 1e-9;
    for (const detail::PreviewVoxel& v : p.voxels) {
        const int idx[3] = {v.a, v.b, v.c};
        for (int k = 0; k < 3; ++k) {
            const int leaf = idx[k] & ~7;
            ASSERT_GE(leaf * h, d.min[k] - eps);
            ASSERT_LE((leaf + 7) * h, d.max[k] + eps);
        }
    }
}

/// Mean direction from lamp L to the voxels within `radius` of it whose density is at least
/// `bright`: the axis of the lamp's bright lobe.
Vec3 beam_direction(const detail::Preview& p, const Light& L, double radius, double bright) {
    Vec3 sum;
    for (const detail::PreviewVoxel& v : p.voxels) {
        const Vec3 X{v.a * p.voxel_size, -v.b * p.voxel_size, -v.c * p.voxel_size};
        const Vec3 d = X - L.position;
        if (length(d) < radius && v.density >= bright) sum = sum + d;
    }
    return normalize(sum);
}

TEST(Preview, EachBeamPointsAlongItsLamp) {
    // The authors' rig (lamps turned 31 degrees inward) and a rig of one lamp looking down and
    // to the side: the beam near each lamp is centred on its axis.
    Rig side = test::two_lamp_rig();
    side.lights.resize(1);
    side.lights[0].position = {0.2, -0.3, 0.1};
    side.lights[0].direction = normalize(Vec3{0.3, 0.5, 0.8});
    for (const Rig& rig : {test::two_lamp_rig(), side}) {
        const detail::Preview p = detail::make_preview(beams_asset(rig), 128);
        for (const Light& L : rig.lights) {
            SCOPED_TRACE(L.name);
            // density 0.6: the source 10^-1.2 of its value 0.1 m down the axis, 0.4 m out
            const Vec3 d = beam_direction(p, L, 0.45, 0.6);
            const double deg = std::acos(std::min(1.0, dot(d, L.direction))) * 180.0 / M_PI;
            EXPECT_LT(deg, 2.0);
        }
    }
}

}  // namespace
}  // namespace deepsea
