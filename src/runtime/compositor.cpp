#include "deepsea/runtime/compositor.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "backscatter_rows.h"
#include "clones.h"
#include "deepsea/colour/srgb.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/forward.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/normals.h"
#include "frame_input.h"
#include "kernels.h"
#include "port_warp.h"

namespace deepsea {

namespace {

/// Per-thread row buffers (structure of arrays), sized once per image width.
struct RowScratch {
    std::vector<float> x, y, z, nx, ny, nz, e, d2, l, d, f, out, dx, t, mask, j;
    ColorRowBuffer color;  ///< the row's colour, where it is not already linear floats
    std::vector<unsigned char> irregular;
    std::vector<int> left;  ///< pixels the backscatter's rows leave to be looked up
    void fit(int n) {
        for (auto* v : {&x, &y, &z, &nx, &ny, &nz, &d2, &t, &mask}) v->resize(n);
        for (auto* v : {&e, &l, &d, &f, &out, &dx, &j}) v->resize(3 * std::size_t(n));
        irregular.resize(n);
        left.resize(n);
    }
};

/// A row of planar depth as the kernels take it: open water 0 (the fast-math kernels must
/// never see NaN or inf). This file is compiled without fast-math: the test sees NaN.
DEEPSEA_CLONES
void sanitise_row(int n, const float* __restrict raw, float* __restrict z) {
    for (int u = 0; u < n; ++u) z[u] = has_surface(raw[u]) ? raw[u] : 0.0f;
}

/// A port row's light path in water, d2: the path t from the port to the hit where the row has
/// one (z > 0), 0 otherwise.
DEEPSEA_CLONES
void port_path_row(int n, const float* __restrict z, const float* __restrict t,
                   float* __restrict d2) {
    for (int u = 0; u < n; ++u) d2[u] = z[u] > 0.0f ? t[u] : 0.0f;
}

/// Whether n >= 32 flags from p on are all 0 (four 8-byte loads).
bool none_of_32(const unsigned char* p) {
    std::uint64_t w[4];
    std::memcpy(w, p, sizeof w);
    return (w[0] | w[1] | w[2] | w[3]) == 0;
}

/// Row v's geometry into s (structure of arrays): its sanitised depth z (open water 0, as the
/// fast-math kernels need), back-projected x = rx z and y = ry z, and normals by central
/// differences in float where all four neighbours are the same surface (the common case,
/// vectorised, kernels::geometry_row); elsewhere (borders, open water, depth steps) the optics
/// rule, one-sided; 0 for open water.
void row_geometry(const Camera& cam, const Image& depth, int v, const float* rx, RowScratch& s) {
    const int W = cam.width, H = cam.height;
    const float* zr = depth.row(v);
    const bool inner = v > 0 && v + 1 < H;
    kernels::geometry_row(W, rx, inner ? float(cam.ray_y(v - 1)) : 0.0f, float(cam.ray_y(v)),
                          inner ? float(cam.ray_y(v + 1)) : 0.0f,
                          inner ? depth.row(v - 1) : nullptr, zr,
                          inner ? depth.row(v + 1) : nullptr, s.x.data(), s.y.data(), s.z.data(),
                          s.nx.data(), s.ny.data(), s.nz.data(), s.irregular.data());
    // Most pixels are regular: 32 flags a test, then 8 (a test a pixel was 6 % of the frame's
    // instructions, eight at a time 1 %).
    for (int u0 = 0; u0 < W; u0 += 32) {
        const int u1 = std::min(u0 + 32, W);
        if (u1 - u0 == 32 && none_of_32(s.irregular.data() + u0)) continue;
        for (int u = u0; u < u1; ++u) {
            std::uint64_t eight = 1;
            if (u + 8 <= u1) std::memcpy(&eight, s.irregular.data() + u, sizeof eight);
            if (eight == 0) {
                u += 7;
                continue;
            }
            if (!s.irregular[u]) continue;
            if (!has_surface(zr[u])) {
                s.nx[u] = s.ny[u] = s.nz[u] = 0.0f;
                continue;
            }
            const Vec3 n = surface_normal(cam, depth, u, v);
            s.nx[u] = float(n.x);
            s.ny[u] = float(n.y);
            s.nz[u] = float(n.z);
        }
    }
}

}  // namespace

Compositor::Compositor(const Camera& camera, const Water& water, const IrradianceSource& lamps,
                       const BackscatterSource& backscatter, const PortRays* port,
                       const ForwardPsfTable* forward_table)
    : m_camera(camera), m_water(water), m_lamps(lamps), m_backscatter(backscatter), m_port(port) {
    if (port && !(port->camera() == camera))
        throw InputError("compositor: the port's rays belong to another camera");
    if (water.forward.enabled && water.forward.model == ForwardModel::PhaseFunction) {
        m_psf_blur.emplace(
            forward_table
                ? ForwardPsf(*forward_table, water, forward_fx(), camera.width, camera.height)
                : ForwardPsf(water, forward_fx(), camera.width, camera.height),
            water.c);
        // the wide scales at true angles off axis; a port's rays keep the pinhole's grids
        if (forward_table && !port)
            m_psf_blur->set_camera(camera.fx, camera.fy, camera.cx, camera.cy);
    }
}

void Compositor::set_exact(bool exact) {
    m_exact = exact;
    if (!m_psf_blur) return;
    m_psf_blur->set_block_distances(!exact);
    m_psf_blur->set_identity_blurs(!exact);
}

double Compositor::forward_fx() const { return m_port ? m_port->water_fx() : m_camera.fx; }

void Compositor::composite(Layers& dst, const ColorView& color, const Image& depth, LayerSet set) {
    run(dst, color, depth, set, nullptr);
}

void Compositor::composite(Layers& dst, const Frame& f, LayerSet set) {
    run(dst, color_view(f), f.depth, set, nullptr);
}

void Compositor::composite(Layers& dst, const ColorView& color, const Image& depth,
                           const FinalRows& rows) {
    run(dst, color, depth, LayerSet::Final, &rows);
}

void Compositor::composite(Layers& dst, const Frame& f, const FinalRows& rows) {
    run(dst, color_view(f), f.depth, LayerSet::Final, &rows);
}

void Compositor::run(Layers& dst, const ColorView& color, const Image& depth, LayerSet set,
                     const FinalRows* rows) {
    const Camera& cam = m_camera;
    const int W = cam.width, H = cam.height;
    if (depth.channels != 1) throw InputError("frame needs a 1-channel depth image");
    const int cw = color.width, ch = color.height;
    // (the message is built only on failure: composite allocates nothing per frame)
    if (cw != depth.width || ch != depth.height) {
        require_same_size(cw, ch, depth.width, depth.height, "colour and depth images");
    }
    if (cw != W || ch != H) {
        throw InputError("frame is " + std::to_string(cw) + "x" + std::to_string(ch) +
                         " but the camera is " + std::to_string(W) + "x" + std::to_string(H));
    }
    const bool all = set == LayerSet::All;
    const bool forward = m_water.forward.enabled;
    const bool psf = forward && m_psf_blur.has_value();
    // Rows handed over are never kept: no final image at all.
    if (rows) {
        dst = Layers{};
    } else {
        dst.resize(W, H, set);
    }
    // Forward scatter needs every pixel's distance and surface radiance before any row can
    // be finished; without it each row is finished where it is shaded, from row buffers.
    if (forward && (m_d2.width != W || m_d2.height != H)) m_d2 = Image(W, H, 1);
    if (forward && (m_surface.width != W || m_surface.height != H)) m_surface = Image(W, H, 3);
    if (psf) m_row_far.resize(H);
    // surfaces tilted to the ray: the transport table's kernel leans (not through a port,
    // whose rays are not the pinhole's)
    const bool lean = psf && m_forward_lean && !m_port && m_psf_blur->psf().from_transport();
    if (lean && (m_lean.width != W || m_lean.height != H)) m_lean = Image(W, H, 2);
    const bool lean_all_rows = ForwardPsfBlur::level_factor(1.0, W, H) == 1;
    if (int(m_rx.size()) != W) {
        m_rx.resize(W);
        for (int u = 0; u < W; ++u) m_rx[u] = float(cam.ray_x(u));
        m_c3.resize(3 * std::size_t(W));
        for (std::size_t k = 0; k < m_c3.size(); ++k) m_c3[k] = float(m_water.c[int(k % 3)]);
    }

    // The image alone, approximations on: B looked up on every `stride`-th row (and the last)
    // in the first pass, the rows between interpolated where the source's bounds allow
    // (backscatter_rows.h). Where the image alone already has a shortcut (the point spread's
    // second pass, which the rows between need), with pinhole rays.
    const BackscatterRowBounds* between =
        !all && psf && !m_exact && !m_port ? m_backscatter.row_bounds() : nullptr;
    // (bounds made for another camera's rows: none)
    if (between && H > 1 && int(between->kinked.size()) != (H - 2) / between->stride + 1)
        between = nullptr;
    const int stride = between ? between->stride : 1;
    const auto key_row = [&](int v) {  // a looked-up row's index in m_back, or -1
        return v % stride == 0 ? v / stride : v == H - 1 ? (H - 1) / stride + 1 : -1;
    };
    if (between) {
        const int keys = key_row(H - 1) + 1;
        if (m_back.width != W || m_back.height != keys) {
            m_back = Image(W, keys, 3);
            m_back_z = Image(W, keys, 1);
        }
    }

    static tbb::enumerable_thread_specific<RowScratch> scratch;
    const float c[3] = {float(m_water.c.r), float(m_water.c.g), float(m_water.c.b)};
    const float G[3] = {float(m_water.forward.G.r), float(m_water.forward.G.g),
                        float(m_water.forward.G.b)};

    // Row v of the image from its planar depth z (open water 0), distance d2 and surface
    // radiance L: final = B + D + F, added in that order whatever the layer set, so that on the
    // exact path every set gives the same final bit for bit (the image alone with the bounded
    // approximations on is within one code of it: docs/runtime.md, "Bounded approximations").
    auto finish = [&](RowScratch& s, int v, const float* z, const float* d2, const float* L) {
        float* out = rows ? s.out.data() : dst.final.row(v);
        if (!between) {
            m_backscatter.backscatter_row(v, W, z, out);
        } else if (const int key = key_row(v); key >= 0) {
            std::copy(m_back.row(key), m_back.row(key) + 3 * std::size_t(W), out);
        } else {
            const int v0 = v - v % stride, v1 = std::min(v0 + stride, H - 1);
            const int k0 = key_row(v0), k1 = key_row(v1);
            // (the row's raw depth: sanitised below only where a pixel is looked up)
            const float* raw = depth.row(v);
            const int left = interpolate_backscatter_row(
                W, float(v - v0) / float(v1 - v0), m_back_z.row(k0), m_back_z.row(k1), raw,
                m_back.row(k0), m_back.row(k1), *between, between->kinked[v0 / stride], out,
                s.left.data());
            if (left > 0) {
                // s.z's other columns hold earlier rows' sanitised depths: never NaN or inf
                for (int q = 0; q < left; ++q) {
                    const int u = s.left[q];
                    s.z[u] = has_surface(raw[u]) ? raw[u] : 0.0f;
                }
                m_backscatter.backscatter_pixels(v, W, s.z.data(), left, s.left.data(), out);
            }
        }
        if (all) std::copy(out, out + 3 * std::size_t(W), dst.backscatter.row(v));
        // The image alone, approximations on: D and F's unblurred part from one table
        // (ForwardPsfBlur::add_direct_row), no exponential a pixel.
        const bool joined = psf && !all && !m_exact;
        if (!joined) {
            kernels::direct_row(W, d2, m_c3.data(), L, s.dx.data(),
                                all ? dst.transmission.row(v) : nullptr,
                                all ? dst.direct.row(v) : nullptr, out);
        }
        if (joined) {
            m_psf_blur->add_direct_row(v, out);
        } else if (psf && !all) {
            m_psf_blur->add_row(v, out);  // F straight into the image, no copy of it
        } else if (forward) {
            float* blurred = s.f.data();
            if (psf) {
                m_psf_blur->row(v, blurred);
            } else {
                m_blur.blend_row(v, d2, blurred);
            }
            // F into its layer, or into D's row buffer, spent by now
            kernels::forward_row(W, d2, c, psf ? nullptr : G, blurred,
                                 all ? dst.forward.row(v) : s.d.data(), out);
        } else if (all) {
            std::fill_n(dst.forward.row(v), 3 * std::size_t(W), 0.0f);
        }
        if (rows) (*rows)(v, out);
    };

    const bool port = m_port != nullptr;
    double z_near = 0.0;
    if (port) {
        // The frame in input pixels: its inverse depth, which the rays' marches read, with each
        // row's nearest surface and window_row_maxima in the same pass (port_depth_row); then
        // its normals and linear colour beside it, which the hits take (port_surface_row).
        if (m_in_surface.width != W || m_in_surface.height != H) {
            m_in_surface = Image(W, H, kPortSurfaceChannels);
            m_inv_depth = Image(W, H, 1);
            m_window_rows = Image((W + kPortStartBlock - 1) / kPortStartBlock, H, 1);
            m_row_near.resize(H);
        }
        tbb::parallel_for(0, H, [&](int v) {
            RowScratch& s = scratch.local();
            s.fit(W);
            sanitise_row(W, depth.row(v), s.z.data());
            m_row_near[v] = port_depth_row(W, s.z.data(), m_inv_depth.row(v), m_window_rows.row(v));
        });
        z_near = *std::min_element(m_row_near.begin(), m_row_near.end());
        // Normals and colour only where the rays can read them: no march starts nearer the
        // camera than the frame's nearest surface (port_row's s_near)
        const PortRays::PixelBox box = m_port->reach(1.001 / z_near);
        tbb::parallel_for(box.y0, box.y1 + 1, [&](int v) {
            RowScratch& s = scratch.local();
            s.fit(W);
            row_geometry(cam, depth, v, m_rx.data(), s);
            const float* J = color_row(color, v, s.color);
            const int x = box.x0;
            port_surface_row(box.x1 - x + 1, s.nx.data() + x, s.ny.data() + x, s.nz.data() + x,
                             J + 3 * x, m_inv_depth.row(v) + x,
                             m_in_surface.row(v) + std::size_t(x) * kPortSurfaceChannels);
        });
        window_nearest_rows(m_window_rows, m_nearest, m_nearest_rows);
        if (forward && (m_hit_z.width != W || m_hit_z.height != H)) m_hit_z = Image(W, H, 1);
        if (all && (dst.mask.width != W || dst.mask.height != H)) dst.mask = Image(W, H, 1);
    } else {
        dst.mask = Image();
        // (the lamps' grid of scattered light is made of pinhole points: through a port each
        // row computes its own, from the hit points)
        m_lamps.begin_frame(cam, depth);
    }
    tbb::parallel_for(0, H, [&](int v) {
        RowScratch& s = scratch.local();
        s.fit(W);
        const float* J;
        if (port) {
            port_row(*m_port, v, m_inv_depth, m_nearest, m_in_surface, z_near,
                     {s.x.data(), s.y.data(), s.z.data(), s.t.data(), s.nx.data(), s.ny.data(),
                      s.nz.data(), s.j.data(), s.mask.data()});
            J = s.j.data();
        } else {
            // Open water becomes z = 0 here: the fast-math kernels must never see NaN or inf.
            row_geometry(cam, depth, v, m_rx.data(), s);
            J = color_row(color, v, s.color);
            if (const int key = between ? key_row(v) : -1; key >= 0) {
                m_backscatter.backscatter_row(v, W, s.z.data(), m_back.row(key));
                lookup_depth_row(W, s.z.data(), between->z_max, m_back_z.row(key));
            }
        }
        const RowGeometry g{v,          W,           s.x.data(),  s.y.data(),
                            s.z.data(), s.nx.data(), s.ny.data(), s.nz.data()};
        m_lamps.irradiance_row(g, s.e.data());

        float* d2 = forward ? m_d2.row(v) : s.d2.data();
        float* L = forward ? m_surface.row(v) : s.l.data();
        kernels::shade_row(W, s.x.data(), s.y.data(), s.z.data(), s.e.data(), J, d2, L);
        if (port) {
            // the light's path in water runs from the port's outer surface, not the camera
            port_path_row(W, s.z.data(), s.t.data(), d2);
            if (all) std::copy(s.mask.begin(), s.mask.begin() + W, dst.mask.row(v));
            if (forward) std::copy(s.z.begin(), s.z.begin() + W, m_hit_z.row(v));
        }
        // (on the even rows only where the blur reads it there: ForwardPsfBlur::prepare)
        if (lean && (v % 2 == 0 || lean_all_rows)) {
            kernels::lean_row(W, m_rx.data(), float(cam.ray_y(v)), s.nx.data(), s.ny.data(),
                              s.nz.data(), float(cam.fx), float(cam.fy), m_lean.row(v));
        }
        // the row's farthest surface, while d2 is in cache (the point spread's table length)
        if (psf) m_row_far[v] = kernels::row_max(W, d2);
        if (all) {
            float* N = dst.normal.row(v);
            for (int u = 0; u < W; ++u) {
                N[3 * u] = s.nx[u];
                N[3 * u + 1] = s.ny[u];
                N[3 * u + 2] = s.nz[u];
            }
            std::copy(s.z.begin(), s.z.begin() + W, dst.depth.row(v));
        }
        if (!forward) finish(s, v, s.z.data(), d2, L);
    });
    if (!forward) return;

    // Forward scatter blurs the surface radiance (not D: w(d2) carries the path to the camera,
    // D's own exp(-c d2) would attenuate it twice) by sigma = sigma_per_m * d2 pixels; d2 is 0
    // for open water.
    if (psf) {
        // a transport table's scene dims beyond the frame as the lamps' light on it (not
        // through a port, whose rays the border pixels do not continue)
        const bool fade = !port && m_psf_blur->psf().from_transport();
        if (fade) edge_falloff(cam, depth, m_lamps, m_psf_blur->psf(), m_beyond);
        const float far = *std::max_element(m_row_far.begin(), m_row_far.end());
        m_psf_blur->prepare(m_surface, m_d2, fade ? &m_beyond : nullptr, std::max(0.0, double(far)),
                            lean ? &m_lean : nullptr);
    } else {
        m_blur.prepare(m_surface, m_d2,
                       float(forward_sigma_px(m_water.forward, forward_fx(), 1.0)));
    }
    tbb::parallel_for(0, H, [&](int v) {
        RowScratch& s = scratch.local();
        s.fit(W);
        if (port) {
            std::copy(m_hit_z.row(v), m_hit_z.row(v) + W, s.z.data());
        } else if (!between) {
            sanitise_row(W, depth.row(v), s.z.data());
        }  // (rows between looked-up rows read the raw depth: finish)
        finish(s, v, s.z.data(), m_d2.row(v), m_surface.row(v));
    });
}

}  // namespace deepsea
