#include "deepsea/runtime/compositor.h"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/forward.h"
#include "deepsea/optics/normals.h"
#include "kernels.h"

namespace deepsea {

namespace {

/// Per-thread row buffers (structure of arrays), sized once per image width.
struct RowScratch {
    std::vector<float> x, y, z, zu, zd, nx, ny, nz, e, d, j, f;
    std::vector<unsigned char> irregular;
    void fit(int n) {
        for (auto* v : {&x, &y, &z, &nx, &ny, &nz}) v->resize(n);
        for (auto* v : {&e, &d, &j, &f}) v->resize(3 * std::size_t(n));
        irregular.resize(n);
    }
};

}  // namespace

Compositor::Compositor(const Camera& camera, const Water& water, const IrradianceSource& lamps,
                       const BackscatterSource& backscatter)
    : m_camera(camera), m_water(water), m_lamps(lamps), m_backscatter(backscatter) {
    if (water.forward.enabled && water.forward.model == ForwardModel::PhaseFunction) {
        m_psf_blur.emplace(ForwardPsf(water, camera.fx, camera.width, camera.height));
    }
}

void Compositor::composite(Layers& dst, const Frame& f, LayerSet set) { run(dst, f, set, nullptr); }

void Compositor::composite(Layers& dst, const Frame& f, const FinalRows& rows) {
    run(dst, f, LayerSet::Final, &rows);
}

void Compositor::run(Layers& dst, const Frame& f, LayerSet set, const FinalRows* rows) {
    const Camera& cam = m_camera;
    const int W = cam.width, H = cam.height;
    const bool coded = f.coded();
    if ((!coded && f.rgb.channels != 3) || f.depth.channels != 1) {
        throw InputError("frame needs a 3-channel colour image and a 1-channel depth image");
    }
    const int cw = f.color_width(), ch = f.color_height();
    const std::size_t samples = 3 * std::size_t(cw) * std::size_t(ch);
    if (coded && (f.codes.bits == 16 ? f.codes.rgb16.size() : f.codes.rgb8.size()) != samples) {
        throw InputError("frame's colour codes do not fill its " + std::to_string(cw) + "x" +
                         std::to_string(ch) + " pixels");
    }
    // (the message is built only on failure: composite allocates nothing per frame)
    if (cw != f.depth.width || ch != f.depth.height) {
        require_same_size(cw, ch, f.depth.width, f.depth.height, "colour and depth images");
    }
    if (cw != W || ch != H) {
        throw InputError("frame is " + std::to_string(cw) + "x" + std::to_string(ch) +
                         " but the camera is " + std::to_string(W) + "x" + std::to_string(H));
    }
    const bool all = set == LayerSet::All;
    const bool forward = m_water.forward.enabled;
    // Rows handed over straight from the first pass: no final image at all.
    const bool stream = rows && !forward;
    if (stream) {
        dst = Layers{};
    } else {
        dst.resize(W, H, set);
    }
    if (m_d2.width != W || m_d2.height != H) m_d2 = Image(W, H, 1);
    if (forward && (m_surface.width != W || m_surface.height != H)) m_surface = Image(W, H, 3);
    if (int(m_rx.size()) != W) {
        m_rx.resize(W);
        for (int u = 0; u < W; ++u) m_rx[u] = float((u - cam.cx) / cam.fx);
    }

    static tbb::enumerable_thread_specific<RowScratch> scratch;
    const float c[3] = {float(m_water.c.r), float(m_water.c.g), float(m_water.c.b)};
    const double sigma_per_m = forward_sigma_px(m_water.forward, cam.fx, 1.0);
    const Image& depth = f.depth;

    m_lamps.begin_frame(cam, depth);
    tbb::parallel_for(0, H, [&](int v) {
        RowScratch& s = scratch.local();
        s.fit(W);
        const float ry = float((v - cam.cy) / cam.fy);
        const float* zr = depth.row(v);
        for (int u = 0; u < W; ++u) {
            const float z = zr[u];
            const float rx = m_rx[u];
            // Open water becomes z = 0 here: the fast-math kernels must never see NaN or inf.
            const float zs = has_surface(z) ? z : 0.0f;
            s.x[u] = rx * zs;
            s.y[u] = ry * zs;
            s.z[u] = zs;
        }
        // Normals: central differences where all four neighbours are the same surface (the
        // common case, vectorised in float); elsewhere the optics rule, one-sided.
        if (v > 0 && v + 1 < H) {
            s.zu.resize(W);
            s.zd.resize(W);
            const float* zu_raw = depth.row(v - 1);
            const float* zd_raw = depth.row(v + 1);
            for (int u = 0; u < W; ++u) {
                s.zu[u] = has_surface(zu_raw[u]) ? zu_raw[u] : 0.0f;
                s.zd[u] = has_surface(zd_raw[u]) ? zd_raw[u] : 0.0f;
            }
            kernels::normals_row(W, m_rx.data(), float((v - 1 - cam.cy) / cam.fy), ry,
                                 float((v + 1 - cam.cy) / cam.fy), s.zu.data(), s.z.data(),
                                 s.zd.data(), s.nx.data(), s.ny.data(), s.nz.data(),
                                 s.irregular.data());
        } else {
            std::fill(s.irregular.begin(), s.irregular.end(), 1);
        }
        for (int u = 0; u < W; ++u) {
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
        const RowGeometry g{v,          W,           s.x.data(),  s.y.data(),
                            s.z.data(), s.nx.data(), s.ny.data(), s.nz.data()};
        m_lamps.irradiance_row(g, s.e.data());

        const float* J = coded ? s.j.data() : f.rgb.row(v);
        if (coded) {
            const std::size_t row = 3 * std::size_t(W) * std::size_t(v);
            if (f.codes.bits == 16) {
                srgb_decode(f.codes.rgb16.data() + row, 3 * std::size_t(W), s.j.data());
            } else {
                srgb_decode(f.codes.rgb8.data() + row, 3 * std::size_t(W), s.j.data());
            }
        }
        float* D = all ? dst.direct.row(v) : s.d.data();
        kernels::shade_row(W, s.x.data(), s.y.data(), s.z.data(), s.e.data(), J, c, D, m_d2.row(v),
                           forward ? m_surface.row(v) : nullptr);
        // final = B + D here; the second pass adds F (in that order whatever the layer set,
        // so that every set gives the same final bit for bit).
        float* B = stream ? s.f.data() : dst.final.row(v);
        m_backscatter.backscatter_row(v, W, s.z.data(), B);
        if (all) std::copy(B, B + 3 * std::size_t(W), dst.backscatter.row(v));
        for (int i = 0; i < 3 * W; ++i) B[i] += D[i];
        if (stream) (*rows)(v, B);
        if (!all) return;
        float* N = dst.normal.row(v);
        for (int u = 0; u < W; ++u) {
            N[3 * u] = s.nx[u];
            N[3 * u + 1] = s.ny[u];
            N[3 * u + 2] = s.nz[u];
        }
        std::copy(s.z.begin(), s.z.begin() + W, dst.depth.row(v));
    });

    // Forward scatter blurs the surface radiance (not D: w(d2) carries the path to the camera,
    // D's own exp(-c d2) would attenuate it twice) by sigma = sigma_per_m * d2 pixels; d2 is 0
    // for open water.
    const bool psf = forward && m_psf_blur;
    if (psf) {
        m_psf_blur->prepare(m_surface, m_d2);
    } else if (forward) {
        m_blur.prepare(m_surface, m_d2, float(sigma_per_m));
    }
    const float G[3] = {float(m_water.forward.G.r), float(m_water.forward.G.g),
                        float(m_water.forward.G.b)};
    // Only the image wanted: final += F straight from the point spread (no T, whose layer is
    // not kept, and no copy of F); with no forward scatter final is already B + D. The same
    // additions as below, so final is the same bit for bit whichever layers are kept.
    if (!all && (psf || !forward)) {
        if (psf) {
            tbb::parallel_for(0, H, [&](int v) {
                m_psf_blur->add_row(v, dst.final.row(v));
                if (rows) (*rows)(v, dst.final.row(v));
            });
        }
        return;
    }
    tbb::parallel_for(0, H, [&](int v) {
        // blurred, and T and F when their layers are not kept
        thread_local std::vector<float> row;
        row.resize(9 * std::size_t(W));
        float* blurred = row.data();
        if (psf) {
            m_psf_blur->row(v, blurred);
        } else if (forward) {
            m_blur.blend_row(v, m_d2.row(v), blurred);
        }
        float* T = all ? dst.transmission.row(v) : blurred + 3 * W;
        float* F = all ? dst.forward.row(v) : blurred + 6 * W;
        kernels::finish_row(W, m_d2.row(v), c, psf ? nullptr : G, forward ? blurred : nullptr, T, F,
                            dst.final.row(v));
        if (rows) (*rows)(v, dst.final.row(v));
    });
}

}  // namespace deepsea
