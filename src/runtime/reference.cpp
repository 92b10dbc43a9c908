#include "deepsea/runtime/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/direct.h"
#include "deepsea/optics/forward.h"
#include "deepsea/optics/normals.h"
#include "deepsea/optics/transmission.h"

namespace deepsea {

double open_water_depth(const Water& water, const ReferenceOptions& opt) {
    if (opt.open_water_z > 0.0) return opt.open_water_z;
    const double c_min = std::min({water.c.r, water.c.g, water.c.b});
    // exp(-c t) = 1e-9 on the way back alone; the lamps' path only makes it smaller.
    return c_min > 0.0 ? std::log(1e9) / c_min : 1e3;
}

namespace {

void check_inputs(const Camera& camera, const Image& rgb, const Image& zdepth) {
    if (rgb.channels != 3) throw InputError("colour image must have 3 channels");
    if (zdepth.channels != 1) throw InputError("depth image must have 1 channel");
    require_same_size(rgb, zdepth, "colour and depth images");
    if (rgb.width != camera.width || rgb.height != camera.height) {
        throw InputError("images are " + std::to_string(rgb.width) + "x" +
                         std::to_string(rgb.height) + " but the camera is " +
                         std::to_string(camera.width) + "x" + std::to_string(camera.height));
    }
}

void put(Image& img, int u, int v, const Rgb& x) {
    float* p = &img.at(u, v);
    p[0] = float(x.r);
    p[1] = float(x.g);
    p[2] = float(x.b);
}

Rgb get(const Image& img, int u, int v) {
    const float* p = img.data.data() + img.index(u, v);
    return {p[0], p[1], p[2]};
}

/// Exact forward scatter: every pixel gathers the surface radiance (the direct signal before
/// the path to the camera: w(d) carries that path) with its own Gaussian (sigma from its own
/// distance), truncated at 4 sigma and normalised over in-image pixels.
void forward_scatter_exact(const Camera& cam, const Water& water, const Image& zdepth,
                           const Image& surface, Layers& out) {
    const ForwardScatter& fs = water.forward;
    tbb::parallel_for(0, cam.height, [&](int v) {
        std::vector<double> g;
        for (int u = 0; u < cam.width; ++u) {
            const double z = zdepth.at(u, v);
            if (!has_surface(z)) continue;
            const double d2 = length(cam.point(u, v, z));
            const Rgb w = forward_weight(fs, water.c, d2);
            if (w.r == 0.0 && w.g == 0.0 && w.b == 0.0) continue;  // F = 0, skip the gather
            const double sigma = std::min(forward_sigma_px(fs, cam.fx, d2),
                                          max_forward_sigma_px(cam.width, cam.height));
            Rgb blurred;
            if (sigma < 0.25) {
                blurred = get(surface, u, v);
            } else {
                const int r = int(std::ceil(4.0 * sigma));
                g.resize(2 * r + 1);
                for (int i = -r; i <= r; ++i) g[i + r] = std::exp(-0.5 * i * i / (sigma * sigma));
                double wsum = 0.0;
                for (int y = std::max(0, v - r); y <= std::min(cam.height - 1, v + r); ++y) {
                    const double gy = g[y - v + r];
                    for (int x = std::max(0, u - r); x <= std::min(cam.width - 1, u + r); ++x) {
                        const double k = gy * g[x - u + r];
                        blurred += get(surface, x, y) * k;
                        wsum += k;
                    }
                }
                blurred = blurred / wsum;
            }
            put(out.forward, u, v, w * blurred);
        }
    });
}

}  // namespace

Layers render_reference(const Camera& cam, const Rig& rig, const Water& water, const Image& rgb,
                        const Image& zdepth, const ReferenceOptions& opt, const Parallel& par) {
    check_inputs(cam, rgb, zdepth);
    validate(opt.quadrature);
    Layers out;
    out.resize(cam.width, cam.height);
    const double z_open = open_water_depth(water, opt);
    // Surface radiance J/pi E: what the forward blur spreads.
    Image surface(cam.width, cam.height, 3);

    // Rows in parallel; progress (and cancelling) per row.
    parallel_for(
        std::size_t(cam.height),
        [&](std::size_t begin, std::size_t end) {
            for (int v = int(begin); v < int(end); ++v) {
                for (int u = 0; u < cam.width; ++u) {
                    const Vec3 r = cam.ray(u, v);
                    const Vec3 dir = normalize(r);
                    const double z = zdepth.at(u, v);
                    if (has_surface(z)) {
                        const Vec3 P = r * z;
                        const Vec3 n = surface_normal(cam, zdepth, u, v);
                        const double d2 = length(P);
                        const Rgb L = surface_radiance(rig, water, P, n, get(rgb, u, v));
                        put(surface, u, v, L);
                        const Rgb T = transmission(water.c, d2);
                        put(out.direct, u, v, L * T);
                        put(out.transmission, u, v, T);
                        put(out.normal, u, v, {n.x, n.y, n.z});
                        out.depth.at(u, v) = float(z);
                        put(out.backscatter, u, v,
                            backscatter_integral(rig, water, dir, 0.0, d2, opt.quadrature).value);
                    } else {
                        const double t = z_open * length(r);
                        put(out.backscatter, u, v,
                            backscatter_integral(rig, water, dir, 0.0, t, opt.quadrature).value);
                    }
                }
            }
        },
        par.or_grain(1));
    if (water.forward.enabled) {
        in_arena(par.threads, [&] { forward_scatter_exact(cam, water, zdepth, surface, out); });
    }
    for (std::size_t i = 0; i < out.final.data.size(); ++i) {
        out.final.data[i] = out.direct.data[i] + out.forward.data[i] + out.backscatter.data[i];
    }
    return out;
}

}  // namespace deepsea
