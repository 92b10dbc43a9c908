#include "deepsea/asset/asset.h"

#include <algorithm>
#include <string>

#include "deepsea/asset/asset_file.h"
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

WorldBox frustum_extent(const Camera& cam, double z_max) {
    // Camera-frame x / z and y / z of the image's outer pixel edges; the apex adds 0.
    const double x0 = cam.ray_x(-0.5), x1 = cam.ray_x(cam.width - 0.5);
    const double y0 = cam.ray_y(-0.5), y1 = cam.ray_y(cam.height - 0.5);
    WorldBox box;
    box.min = {std::min(0.0, x0) * z_max, -std::max(0.0, y1) * z_max, -z_max};
    box.max = {std::max(0.0, x1) * z_max, -std::min(0.0, y0) * z_max, 0.0};
    return box;
}

void check_port(const Asset& asset, const std::optional<Port>& port, bool pinhole_with_port) {
    const std::optional<Port>& baked = asset.info.port;
    if (!baked && (!port || pinhole_with_port)) return;
    if (baked && port && same_rays(*baked, *port)) return;
    const std::string asset_side = baked ? "the asset was baked through a " + describe(*baked)
                                         : std::string("the asset was baked without a port");
    const std::string frame_side = port ? "the frames' camera looks through a " + describe(*port)
                                        : std::string("the frames' camera has no port");
    throw AssetError(asset_side + ", " + frame_side +
                     (baked ? ": render with the asset's camera.port (render --camera), or bake "
                              "the asset with the frames' port"
                            : ": bake the asset with the frames' camera.port"));
}

void check_camera(const Asset& asset, const Camera& camera) {
    check_same_view(asset.info.camera, camera);
}

}  // namespace deepsea
