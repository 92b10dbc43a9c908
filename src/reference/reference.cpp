#include "deepsea/reference/reference.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/direct.h"
#include "deepsea/optics/forward.h"
#include "deepsea/optics/forward_psf.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/normals.h"
#include "deepsea/optics/port_hit.h"
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
/// water path `dist`, metres, 0 without a surface; fx the pixels per radian of the water-side
/// rays), truncated at 4 sigma and normalised over in-image pixels.
void forward_scatter_exact(const Camera& cam, const Water& water, double fx,
                           const std::vector<double>& dist, const Image& surface, Layers& out) {
    const ForwardScatter& fs = water.forward;
    tbb::parallel_for(0, cam.height, [&](int v) {
        std::vector<double> g;
        for (int u = 0; u < cam.width; ++u) {
            const double d2 = dist[std::size_t(v) * cam.width + u];
            if (!(d2 > 0.0)) continue;
            const Rgb w = forward_weight(fs, water.c, d2);
            if (w.r == 0.0 && w.g == 0.0 && w.b == 0.0) continue;  // F = 0, skip the gather
            const double sigma =
                std::min(forward_sigma_px(fs, fx, d2), max_forward_sigma_px(cam.width, cam.height));
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

/// One separable pass of a Gaussian of sigma pixels along rows (step 1) or columns, in place
/// over 3 interleaved channels, truncated at 4 sigma and normalised over in-image pixels.
void gaussian_pass(std::vector<double>& img, int W, int H, double sigma, bool along_rows) {
    const int n = along_rows ? W : H, lines = along_rows ? H : W;
    const int r = std::min(int(std::ceil(4.0 * sigma)), n);
    std::vector<double> g(2 * r + 1);
    for (int i = -r; i <= r; ++i) g[i + r] = std::exp(-0.5 * i * i / (sigma * sigma));
    tbb::parallel_for(0, lines, [&](int line) {
        const auto at = [&](int i) -> double* {
            return img.data() +
                   3 * (along_rows ? std::size_t(line) * W + i : std::size_t(i) * W + line);
        };
        std::vector<double> out(3 * std::size_t(n), 0.0);
        for (int i = 0; i < n; ++i) {
            double wsum = 0.0, acc[3] = {0.0, 0.0, 0.0};
            for (int k = std::max(0, i - r); k <= std::min(n - 1, i + r); ++k) {
                const double w = g[k - i + r];
                const double* p = at(k);
                for (int c = 0; c < 3; ++c) acc[c] += w * p[c];
                wsum += w;
            }
            for (int c = 0; c < 3; ++c) out[3 * i + c] = acc[c] / wsum;
        }
        for (int i = 0; i < n; ++i) {
            for (int c = 0; c < 3; ++c) at(i)[c] = out[3 * i + c];
        }
    });
}

/// Exact forward scatter from the phase function (optics/forward_psf.h): for every scale j,
/// the surface radiance weighted by that scale's exact share W_j(d) (double, every order),
/// blurred by the scale's Gaussian at full resolution, separable, truncated at 4 sigma and
/// normalised over in-image pixels; summed over the scales. d and fx as forward_scatter_exact's.
void forward_psf_exact(const Camera& cam, const Water& water, double fx,
                       const std::vector<double>& d, const Image& surface, Layers& out) {
    const int W = cam.width, H = cam.height;
    const ForwardPsf psf(water, fx, W, H);
    std::vector<double> F(3 * d.size(), 0.0), src(F.size());
    for (int j = 0; j < psf.scales(); ++j) {
        tbb::parallel_for(0, H, [&](int v) {
            for (int u = 0; u < W; ++u) {
                const std::size_t i = std::size_t(v) * W + u;
                const Rgb x = d[i] > 0.0 ? psf.weight(j, d[i]) * get(surface, u, v) : Rgb{};
                for (int c = 0; c < 3; ++c) src[3 * i + c] = x[c];
            }
        });
        if (psf.sigma_px(j) > 0.0) {
            gaussian_pass(src, W, H, psf.sigma_px(j), true);
            gaussian_pass(src, W, H, psf.sigma_px(j), false);
        }
        for (std::size_t i = 0; i < F.size(); ++i) F[i] += src[i];
    }
    for (std::size_t i = 0; i < F.size(); ++i) out.forward.data[i] = float(F[i]);
}

/// One pixel through the port: its water-side ray (the green channel's, as the renderer's),
/// where it meets the depth map (find_port_hit: the runtime's hit definition, in double), the
/// surface there lit as a pinhole pixel's (colour and normal from the same taps, the normal
/// renormalised), the light's path in water from the port's outer surface. Returns the water path
/// to the surface (0: none).
double port_pixel(const Camera& cam, const Rig& rig, const Water& water, const Port& port,
                  const Image& rgb, const Image& zdepth, const Image& inv, double z_near,
                  double z_open, const Quadrature& q, int u, int v, Image& surface, Layers& out) {
    const PortRay ray = trace_port(port, cam, u, v);
    if (!ray.valid()) return 0.0;  // (check_port_view refuses such a port)
    const Vec3 o = ray.origin, w = ray.direction[1];
    const PortHit hit = find_port_hit(cam, inv, project_ray(cam, o, w), o, w, z_near);
    out.mask.at(u, v) = hit.seen() ? 1.0f : 0.0f;
    if (hit.kind != PortHitKind::Surface) {
        // open water, or unseen (rendered as open water): to the open-water depth
        const double t = std::max(0.0, (z_open - o.z) / w.z);
        put(out.backscatter, u, v, backscatter_integral(rig, water, o, w, 0.0, t, q).value);
        return 0.0;
    }
    Rgb J;
    Vec3 n;
    for (int i = 0; i < hit.taps.count; ++i) {
        J += get(rgb, hit.taps.x[i], hit.taps.y[i]) * hit.taps.w[i];
        n = n + surface_normal(cam, zdepth, hit.taps.x[i], hit.taps.y[i]) * hit.taps.w[i];
    }
    if (length(n) > 0.0) n = normalize(n);
    const Vec3 P = o + w * hit.t;
    const Rgb L = surface_radiance(rig, water, P, n, J);
    put(surface, u, v, L);
    const Rgb T = transmission(water.c, hit.t);
    put(out.direct, u, v,
        {direct_signal(L.r, T.r), direct_signal(L.g, T.g), direct_signal(L.b, T.b)});
    put(out.transmission, u, v, T);
    put(out.normal, u, v, {n.x, n.y, n.z});
    out.depth.at(u, v) = float(hit.z);
    put(out.backscatter, u, v, backscatter_integral(rig, water, o, w, 0.0, hit.t, q).value);
    return hit.t;
}

}  // namespace

Layers render_reference(const Camera& cam, const Rig& rig, const Water& water, const Image& rgb,
                        const Image& zdepth, const ReferenceOptions& opt, const Parallel& par) {
    check_inputs(cam, rgb, zdepth);
    validate(opt.quadrature);
    const Port* port = opt.port ? &*opt.port : nullptr;
    if (port) {
        validate(*port);
        check_port_view(*port, cam);
        check_port_sees_input(*port, cam);
    }
    Layers out;
    out.resize(cam.width, cam.height);
    const double z_open = open_water_depth(water, opt);
    // Surface radiance J/pi E: what the forward blur spreads; the water path to each surface.
    Image surface(cam.width, cam.height, 3);
    std::vector<double> dist(std::size_t(cam.width) * cam.height, 0.0);
    Image inv;
    double z_near = std::numeric_limits<double>::infinity();
    if (port) {
        out.mask = Image(cam.width, cam.height, 1);
        inv = inverse_depth(zdepth);
        for (const float z : zdepth.data)
            if (has_surface(z)) z_near = std::min(z_near, double(z));
    }

    // Rows in parallel; progress (and cancelling) per row.
    parallel_for(
        std::size_t(cam.height),
        [&](std::size_t begin, std::size_t end) {
            for (int v = int(begin); v < int(end); ++v) {
                for (int u = 0; u < cam.width; ++u) {
                    double& d2 = dist[std::size_t(v) * cam.width + u];
                    if (port) {
                        d2 = port_pixel(cam, rig, water, *port, rgb, zdepth, inv, z_near, z_open,
                                        opt.quadrature, u, v, surface, out);
                        continue;
                    }
                    const Vec3 r = cam.ray(u, v);
                    const Vec3 dir = normalize(r);
                    const double z = zdepth.at(u, v);
                    if (has_surface(z)) {
                        const Vec3 P = r * z;
                        const Vec3 n = surface_normal(cam, zdepth, u, v);
                        d2 = length(P);
                        const Rgb L = surface_radiance(rig, water, P, n, get(rgb, u, v));
                        put(surface, u, v, L);
                        const Rgb T = transmission(water.c, d2);
                        put(out.direct, u, v,
                            {direct_signal(L.r, T.r), direct_signal(L.g, T.g),
                             direct_signal(L.b, T.b)});
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
        // the forward blur's angular scale: the water-side rays' (docs/ports.md)
        const double fx = port ? port_water_fx(*port, cam) : cam.fx;
        in_arena(par.threads, [&] {
            if (water.forward.model == ForwardModel::PhaseFunction) {
                forward_psf_exact(cam, water, fx, dist, surface, out);
            } else {
                forward_scatter_exact(cam, water, fx, dist, surface, out);
            }
        });
    }
    for (std::size_t i = 0; i < out.final.data.size(); ++i) {
        out.final.data[i] = out.direct.data[i] + out.forward.data[i] + out.backscatter.data[i];
    }
    return out;
}

Image radiance_at_camera(const Image& image, const Port& port, const Camera& cam) {
    if (image.channels != 3 || image.width != cam.width || image.height != cam.height)
        throw InputError("radiance_at_camera: the image is not the camera's RGB image");
    Image out = image;
    tbb::parallel_for(0, cam.height, [&](int v) {
        for (int u = 0; u < cam.width; ++u) {
            const Rgb k = port_radiance_factor(port, trace_port(port, cam, u, v));
            for (int c = 0; c < 3; ++c) out.at(u, v, c) = float(k[c] * image.at(u, v, c));
        }
    });
    return out;
}

}  // namespace deepsea
