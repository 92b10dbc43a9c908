#include "preview.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/asset/asset_file.h"

namespace deepsea::detail {

namespace {

/// Rec. 709 luminance of linear RGB.
inline double luminance(double r, double g, double b) {
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

constexpr double kDepthCut = 1e-2;    // preview depth: in-scatter below 1 % of the max beyond
constexpr double kDensityCut = 1e-3;  // voxels below this density stay background (sparse)
// Finest preview voxel, metres: a tenth of a millimetre shows nothing more in a viewer, and
// OpenVDB refuses a linear transform of voxels below about 14 micrometres (ArithmeticError).
constexpr double kMinPreviewVoxel = 1e-4;

/// Leaf-safe index range [lo, hi] of one axis: voxels a = lo .. hi at world a * h whose whole
/// 8-voxel leaf node [8q, 8q + 7] lies in [wmin, wmax]. Blender frames a grid by its leaf nodes.
void leaf_safe_range(double wmin, double wmax, double h, int& lo, int& hi) {
    const double eps = 1e-9;
    lo = 8 * int(std::ceil(wmin / h / 8.0 - eps));
    hi = 8 * int(std::floor((wmax / h - 7.0) / 8.0 + eps)) + 7;
}

}  // namespace

double preview_voxel_size(const Camera& cam, double z_max, int max_depth, int max_across,
                          double& depth) {
    const double pixels = std::max(1.0, double(std::max(cam.width, cam.height)) / max_across);
    const double footprint = pixels * depth / std::min(cam.fx, cam.fy);
    const double h = std::max({footprint, depth / max_depth, kMinPreviewVoxel});
    if (8.0 * h <= depth * (1.0 + 1e-9)) {
        // Whole leaf nodes along the depth, rounded down: voxels no smaller than both bounds.
        const double leaves = std::floor(depth / h / 8.0 + 1e-9);
        return depth / (8.0 * std::max(leaves, 1.0));
    }
    // Less than one leaf node deep (a wide field of view): keep the footprint's coarse voxel,
    // but at least 2 of them deep so that the light near the camera shows, and cover the depth
    // in fewer than 8 of them, as long as their leaf node (8 voxels from the camera) stays
    // within z_max; else depth / 8, 8 deep. Shrinking the voxel to depth / 8 always (as before)
    // put 8 W / fx x 8 H / fy voxels in the far slab: 741 MB at fx 1 on a 320x240 image.
    double voxel = std::max(std::min(h, 0.5 * depth), kMinPreviewVoxel);
    if (8.0 * voxel > z_max * (1.0 + 1e-9)) voxel = std::max(depth / 8.0, kMinPreviewVoxel);
    depth = voxel * std::ceil(depth / voxel - 1e-9);
    return voxel;
}

Preview make_preview(const Asset& asset, int max_depth, int max_across) {
    const Lattice& l = asset.lattice();
    const Camera& cam = asset.info.camera;
    const int K = l.slabs();
    Preview out;

    // In-scatter per lattice cell, dB/dt over each segment (radiance per metre of path):
    // the derivative of exactly the piecewise-linear B the runtime interpolates.
    std::vector<float> s(std::size_t(l.ni) * l.nj * K * 3);
    double lum_max = 0.0;
    for (int i = 0; i < l.ni; ++i) {
        for (int j = 0; j < l.nj; ++j) {
            const double stretch = length(cam.ray(l.u(i), l.v(j)));  // t = z |r|
            const float* b = asset.values.data() + asset.index(i, j, 0);
            float* d = s.data() + (std::size_t(i) * l.nj + j) * K * 3;
            for (int k = 0; k < K; ++k) {
                const double dt = (l.z[k + 1] - l.z[k]) * stretch;
                for (int c = 0; c < 3; ++c) {
                    d[3 * k + c] = float(std::max(0.0, (b[3 * (k + 1) + c] - b[3 * k + c]) / dt));
                }
                lum_max = std::max(lum_max, luminance(d[3 * k], d[3 * k + 1], d[3 * k + 2]));
            }
        }
    }
    if (!(lum_max > 0.0)) return out;

    int k_last = 0;
    for (std::size_t n = 0; n < s.size() / 3; ++n) {
        if (luminance(s[3 * n], s[3 * n + 1], s[3 * n + 2]) >= kDepthCut * lum_max) {
            k_last = std::max(k_last, int(n % K));
        }
    }
    out.depth = l.z[k_last + 1];
    out.voxel_size = preview_voxel_size(cam, l.z_max(), max_depth, max_across, out.depth);
    out.density_scale = lum_max;
    const double h = out.voxel_size;
    const int slabs = int(std::lround(out.depth / h));  // a multiple of 8, or below 8

    std::vector<double> mid(K);
    for (int k = 0; k < K; ++k) mid[k] = 0.5 * (l.z[k] + l.z[k + 1]);
    // The image's frustum: pixel edges -0.5 .. size - 0.5 (the lattice may reach beyond).
    const double u_lo = -0.5, u_hi = cam.width - 0.5, v_lo = -0.5, v_hi = cam.height - 0.5;
    const WorldBox box = frustum_extent(cam, l.z_max());
    int a_lo, a_hi, b_lo, b_hi;
    leaf_safe_range(box.min.x, box.max.x, h, a_lo, a_hi);
    leaf_safe_range(box.min.y, box.max.y, h, b_lo, b_hi);

    std::vector<std::vector<PreviewVoxel>> slices(slabs);
    std::vector<long> trimmed(slabs, 0);
    tbb::parallel_for(0, slabs, [&](int n) {
        const double Z = (n + 1) * h;
        // In-scatter at depth Z, linear between segment midpoints, for every column.
        const int m1 = int(std::upper_bound(mid.begin(), mid.end(), Z) - mid.begin());
        const int m0 = std::max(m1 - 1, 0);
        const int m1c = std::min(m1, K - 1);
        const double w =
            m1c > m0 ? std::clamp((Z - mid[m0]) / (mid[m1c] - mid[m0]), 0.0, 1.0) : 0.0;
        std::vector<float> at(std::size_t(l.ni) * l.nj * 3);
        for (std::size_t col = 0; col < std::size_t(l.ni) * l.nj; ++col) {
            const float* d = s.data() + col * K * 3;
            for (int c = 0; c < 3; ++c) {
                at[3 * col + c] = float(d[3 * m0 + c] + w * (d[3 * m1c + c] - d[3 * m0 + c]));
            }
        }
        std::vector<PreviewVoxel>& vox = slices[n];
        const int a0 = int(std::ceil(cam.ray_x(u_lo) * Z / h));
        const int a1 = int(std::floor(cam.ray_x(u_hi) * Z / h));
        // World y is up: b = -Y / h.
        const int b0 = int(std::ceil(-cam.ray_y(v_hi) * Z / h));
        const int b1 = int(std::floor(-cam.ray_y(v_lo) * Z / h));
        // Voxels in the frustum whose leaf node would reach out of its box: only at the far
        // corners, when the preview reaches z_max.
        trimmed[n] = long(b1 - b0 + 1) * (a1 - a0 + 1) -
                     long(std::max(0, std::min(b1, b_hi) - std::max(b0, b_lo) + 1)) *
                         std::max(0, std::min(a1, a_hi) - std::max(a0, a_lo) + 1);
        for (int bb = std::max(b0, b_lo); bb <= std::min(b1, b_hi); ++bb) {
            const double v = cam.fy * (-bb * h) / Z + cam.cy;
            const double y = std::clamp(v / l.step, 0.0, double(l.nj - 1));
            const int j0 = std::min(int(y), std::max(l.nj - 2, 0));
            const int j1 = std::min(j0 + 1, l.nj - 1);
            const double wy = y - j0;
            for (int a = std::max(a0, a_lo); a <= std::min(a1, a_hi); ++a) {
                const double u = cam.fx * (a * h) / Z + cam.cx;
                const double x = std::clamp(u / l.step, 0.0, double(l.ni - 1));
                const int i0 = std::min(int(x), std::max(l.ni - 2, 0));
                const int i1 = std::min(i0 + 1, l.ni - 1);
                const double wx = x - i0;
                double rgb[3];
                for (int c = 0; c < 3; ++c) {
                    const auto f = [&](int i, int j) {
                        return at[3 * (std::size_t(i) * l.nj + j) + c];
                    };
                    const double top = f(i0, j0) + wx * (f(i1, j0) - f(i0, j0));
                    const double bottom = f(i0, j1) + wx * (f(i1, j1) - f(i0, j1));
                    rgb[c] = top + wy * (bottom - top);
                }
                const double density = luminance(rgb[0], rgb[1], rgb[2]) / lum_max;
                if (!(density >= kDensityCut)) continue;
                const double peak = std::max({rgb[0], rgb[1], rgb[2]});
                vox.push_back({a,
                               bb,
                               -(n + 1),
                               float(density),
                               {float(rgb[0] / peak), float(rgb[1] / peak), float(rgb[2] / peak)}});
            }
        }
    });
    for (long t : trimmed) out.trimmed += t;
    std::size_t total = 0;
    for (const auto& v : slices) total += v.size();
    out.voxels.reserve(total);
    for (const auto& v : slices) out.voxels.insert(out.voxels.end(), v.begin(), v.end());
    return out;
}

}  // namespace deepsea::detail
