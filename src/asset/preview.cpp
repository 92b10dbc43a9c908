#include "preview.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/optics/lamp.h"

namespace deepsea::detail {

namespace {

/// Rec. 709 luminance of linear RGB.
inline double luminance(const Rgb& x) { return 0.2126 * x.r + 0.7152 * x.g + 0.0722 * x.b; }

/// Leaf-safe index range [lo, hi] of one axis: voxels a = lo .. hi at world a * h whose whole
/// 8-voxel leaf node [8q, 8q + 7] lies in [wmin, wmax]. Blender frames a grid by its leaf nodes.
void leaf_safe_range(double wmin, double wmax, double h, int& lo, int& hi) {
    const double eps = 1e-9;
    lo = 8 * int(std::ceil(wmin / h / 8.0 - eps));
    hi = 8 * int(std::floor((wmax / h - 7.0) / 8.0 + eps)) + 7;
}

/// The source of one lamp alone, at distance r on its axis, with its RID's peak instead of
/// RID(0) (a measured table may peak off the axis).
double on_axis(const Light& L, const Water& water, double r, double rid_peak) {
    const double spread = lamp_spread(r, 1.0);
    Rgb s;
    for (int c = 0; c < 3; ++c) {
        s[c] = water.b[c] * lamp_term(L.intensity[c], rid_peak, spread, water.c[c], r);
    }
    return luminance(s);
}

double rid_peak(const Light& L) {
    double peak = 0.0;
    for (int d = 0; d <= 180; ++d) peak = std::max(peak, L.rid(d * M_PI / 180.0));
    return peak;
}

/// The reference: the brightest lamp's source at kBeamReference on its axis.
double density_scale(const Rig& rig, const Water& water) {
    double s = 0.0;
    for (const Light& L : rig.lights) {
        s = std::max(s, on_axis(L, water, kBeamReference, rid_peak(L)));
    }
    return s;
}

}  // namespace

double beam_source(const Rig& rig, const Water& water, const Vec3& X) {
    Rgb sum;
    for (const Light& L : rig.lights) {
        const Vec3 to_light = L.position - X;
        const double d = length(to_light);
        if (!(d > 0.0)) continue;  // the lamp itself
        // Facing the lamp (n = w): the irradiance a small sphere of water there receives.
        const auto v = [](const Vec3& a) { return Vec3T<double>{a.x, a.y, a.z}; };
        const LampGeometry<double> g = lamp_geometry(v(to_light), v(to_light / d), v(L.direction));
        const double rid = L.rid(lamp_angle(g.cos_theta));
        const double spread = lamp_spread(g.d1, g.cos_n);
        for (int c = 0; c < 3; ++c) {
            sum[c] += water.b[c] * lamp_term(L.intensity[c], rid, spread, water.c[c], g.d1);
        }
    }
    return luminance(sum);
}

WorldBox beam_domain(const Rig& rig, const Water& water, const WorldBox& extent) {
    const double scale = density_scale(rig, water);
    double mn[3] = {extent.max.x, extent.max.y, extent.max.z};  // empty
    double mx[3] = {extent.min.x, extent.min.y, extent.min.z};
    for (const Light& L : rig.lights) {
        const double peak = rid_peak(L);
        // Bisection in log r for the distance where the on-axis density falls to kBeamCut.
        double lo = 1e-4, hi = 1e4;
        if (!(beam_density(on_axis(L, water, lo, peak), scale) > kBeamCut)) continue;  // dark
        for (int it = 0; it < 100; ++it) {
            const double mid = std::sqrt(lo * hi);
            (beam_density(on_axis(L, water, mid, peak), scale) > kBeamCut ? lo : hi) = mid;
        }
        const Vec3 p = camera_to_world(L.position);
        for (int a = 0; a < 3; ++a) {
            mn[a] = std::min(mn[a], p[a] - hi);
            mx[a] = std::max(mx[a], p[a] + hi);
        }
    }
    for (int a = 0; a < 3; ++a) {
        mn[a] = std::max(mn[a], extent.min[a]);
        mx[a] = std::min(mx[a], extent.max[a]);
    }
    // in front of the camera's plane (world z <= 0)
    return {{mn[0], mn[1], mn[2]}, {mx[0], mx[1], std::min(mx[2], 0.0)}};
}

Preview make_preview(const Asset& asset, int max_across) {
    const Rig& rig = asset.info.rig;
    const Water& water = asset.info.water;
    Preview out;
    out.density_scale = density_scale(rig, water);
    if (!(out.density_scale > 0.0)) return out;
    out.domain =
        beam_domain(rig, water, frustum_extent(asset.info.camera, asset.lattice().z_max()));
    const WorldBox& d = out.domain;
    double longest = 0.0;
    for (int a = 0; a < 3; ++a) longest = std::max(longest, d.max[a] - d.min[a]);
    if (!(longest > 0.0)) return out;
    const double h = longest / std::max(max_across, 8);
    out.voxel_size = h;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) leaf_safe_range(d.min[a], d.max[a], h, lo[a], hi[a]);
    if (hi[0] < lo[0] || hi[1] < lo[1]) return out;
    if (hi[2] < lo[2]) return out;

    std::vector<std::vector<PreviewVoxel>> slices(std::size_t(hi[2] - lo[2] + 1));
    tbb::parallel_for(lo[2], hi[2] + 1, [&](int c) {
        std::vector<PreviewVoxel>& vox = slices[std::size_t(c - lo[2])];
        for (int b = lo[1]; b <= hi[1]; ++b) {
            for (int a = lo[0]; a <= hi[0]; ++a) {
                // world (a, b, c) h is the camera-frame point (a h, -b h, -c h)
                const double s = beam_source(rig, water, {a * h, -b * h, -c * h});
                const double density = beam_density(s, out.density_scale);
                if (density >= kBeamCut) vox.push_back({a, b, c, float(density)});
            }
        }
    });
    std::size_t total = 0;
    for (const auto& v : slices) total += v.size();
    out.voxels.reserve(total);
    for (const auto& v : slices) out.voxels.insert(out.voxels.end(), v.begin(), v.end());
    return out;
}

}  // namespace deepsea::detail
