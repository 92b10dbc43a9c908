#include "deepsea/asset/asset.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/core/error.h"

namespace deepsea {

const char* to_string(Scattering s) { return s == Scattering::Multiple ? "multiple" : "single"; }

Scattering parse_scattering(const std::string& name) {
    if (name == "single") return Scattering::Single;
    if (name == "multiple") return Scattering::Multiple;
    throw ConfigError("scattering: expected 'single' or 'multiple', got '" + name + "'");
}

void Asset::allocate() {
    const Lattice& l = info.lattice;
    values.assign(std::size_t(l.ni) * l.nj * l.nk() * 3, 0.0f);
}

namespace {

/// Cell and weight of coordinate x (in lattice units) among n nodes, clamped to the lattice.
inline void cell(double x, int n, int& i0, int& i1, double& w) {
    if (!(x > 0.0)) x = 0.0;  // also NaN
    const double last = double(n - 1);
    if (x >= last) {
        i0 = std::max(n - 2, 0);
        i1 = n - 1;
        w = n > 1 ? 1.0 : 0.0;
        return;
    }
    i0 = int(x);
    i1 = i0 + 1;
    w = x - i0;
}

}  // namespace

Rgb Asset::sample(double u, double v, double z) const {
    const Lattice& l = info.lattice;
    if (z <= 0.0) return {};
    int i0, i1, j0, j1;
    double wu, wv;
    cell(u / l.step, l.ni, i0, i1, wu);
    cell(v / l.step, l.nj, j0, j1, wv);
    const DepthPosition d = l.depth_position(z);
    const float* p00 = values.data() + index(i0, j0, d.k);
    const float* p10 = values.data() + index(i1, j0, d.k);
    const float* p01 = values.data() + index(i0, j1, d.k);
    const float* p11 = values.data() + index(i1, j1, d.k);
    Rgb out;
    for (int c = 0; c < 3; ++c) {
        // Linear in z inside each column (the next sample is 3 floats on), then bilinear.
        const double b00 = p00[c] + d.w * (p00[c + 3] - p00[c]);
        const double b10 = p10[c] + d.w * (p10[c + 3] - p10[c]);
        const double b01 = p01[c] + d.w * (p01[c + 3] - p01[c]);
        const double b11 = p11[c] + d.w * (p11[c + 3] - p11[c]);
        const double top = b00 + wu * (b10 - b00);
        const double bottom = b01 + wu * (b11 - b01);
        out[c] = top + wv * (bottom - top);
    }
    return out;
}

std::string describe(const Camera& c) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%dx%d fx=%.6g fy=%.6g cx=%.6g cy=%.6g", c.width, c.height,
                  c.fx, c.fy, c.cx, c.cy);
    return buf;
}

void check_camera(const Asset& asset, const Camera& camera) {
    const Camera& baked = asset.info.camera;
    if (baked == camera || baked.same_view(camera)) return;
    throw AssetError("asset was baked for camera " + describe(baked) +
                     " but the frames come from camera " + describe(camera) +
                     " (a different view; re-bake for this camera)");
}

}  // namespace deepsea
