#include "deepsea/asset/asset.h"

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

Rgb Asset::sample(double u, double v, double z) const {
    const Lattice& l = info.lattice;
    if (z <= 0.0) return {};
    const LatticeCell<double> cu = lattice_cell(u / l.step, l.ni);
    const LatticeCell<double> cv = lattice_cell(v / l.step, l.nj);
    const DepthPosition d = l.depth_position(z);
    const float* p00 = values.data() + index(cu.i0, cv.i0, d.k);
    const float* p10 = values.data() + index(cu.i1, cv.i0, d.k);
    const float* p01 = values.data() + index(cu.i0, cv.i1, d.k);
    const float* p11 = values.data() + index(cu.i1, cv.i1, d.k);
    // Linear in z inside each column (the next sample is 3 floats on), then bilinear.
    const auto in_z = [&](const float* p, int c) { return lerp<double>(p[c], p[c + 3], d.w); };
    Rgb out;
    for (int c = 0; c < 3; ++c) {
        const double top = lerp(in_z(p00, c), in_z(p10, c), cu.w);
        const double bottom = lerp(in_z(p01, c), in_z(p11, c), cu.w);
        out[c] = lerp(top, bottom, cv.w);
    }
    return out;
}

void check_camera(const Asset& asset, const Camera& camera) {
    check_same_view(asset.info.camera, camera);
}

}  // namespace deepsea
