#include "preview.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace deepsea::detail {

namespace {

/// Rec. 709 luminance of linear RGB.
inline double luminance(double r, double g, double b) {
    return 0.2126 * r + 0.7152 * g + 0.0722 * b;
}

constexpr double kDepthCut = 1e-2;    // preview depth: in-scatter below 1 % of the max beyond
constexpr double kDensityCut = 1e-3;  // voxels below this density stay background (sparse)

}  // namespace

Preview make_preview(const Asset& asset, int resolution) {
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
    out.voxel_size = out.depth / resolution;
    out.density_scale = lum_max;
    const double h = out.voxel_size;

    std::vector<double> mid(K);
    for (int k = 0; k < K; ++k) mid[k] = 0.5 * (l.z[k] + l.z[k + 1]);
    const double u_max = l.u(l.ni - 1), v_max = l.v(l.nj - 1);

    std::vector<std::vector<PreviewVoxel>> slices(resolution);
    tbb::parallel_for(0, resolution, [&](int n) {
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
        const int a0 = int(std::ceil((0.0 - cam.cx) / cam.fx * Z / h));
        const int a1 = int(std::floor((u_max - cam.cx) / cam.fx * Z / h));
        // World y is up: b = -Y / h.
        const int b0 = int(std::ceil(-(v_max - cam.cy) / cam.fy * Z / h));
        const int b1 = int(std::floor(-(0.0 - cam.cy) / cam.fy * Z / h));
        for (int bb = b0; bb <= b1; ++bb) {
            const double v = cam.fy * (-bb * h) / Z + cam.cy;
            const double y = std::clamp(v / l.step, 0.0, double(l.nj - 1));
            const int j0 = std::min(int(y), std::max(l.nj - 2, 0));
            const int j1 = std::min(j0 + 1, l.nj - 1);
            const double wy = y - j0;
            for (int a = a0; a <= a1; ++a) {
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
    std::size_t total = 0;
    for (const auto& v : slices) total += v.size();
    out.voxels.reserve(total);
    for (const auto& v : slices) out.voxels.insert(out.voxels.end(), v.begin(), v.end());
    return out;
}

}  // namespace deepsea::detail
