// Lamp shadows on every step-th pixel, brought to every pixel (docs/snow-shadows.md, "Lamp
// shadows", "Reduced resolution"). The sweep itself is lamp_shadows.cpp's, run on a camera whose
// pixel (i, j) is the frame's pixel (step i, step j) and on those pixels' depths (a subsample, not
// an average: every swept depth is one the frame has, so no sample lies between two surfaces).

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "clones.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/normals.h"
#include "deepsea/runtime/lamp_shadows.h"

namespace deepsea {

namespace {

/// The camera whose pixel (i, j) sees along the ray of `cam`'s pixel (step i, step j): the
/// frame's size rounded up so that the last sample is the frame's last pixel or before it.
Camera coarse_camera(const Camera& cam, int step) {
    Camera c;
    c.width = (cam.width - 1) / step + 1;
    c.height = (cam.height - 1) / step + 1;
    c.fx = cam.fx / step;
    c.fy = cam.fy / step;
    c.cx = cam.cx / step;
    c.cy = cam.cy / step;
    return c;
}

/// Row v of the full-resolution visibility from the coarse rows j0 and j1 (the samples above
/// and below it, j1 = j0 at the last row; ty: v's fraction of the way from j0 to j1; za, zb:
/// the frame's rows j0 step and j1 step, the samples' depths every step-th value). A pixel
/// takes the bilinear mean of the four samples around it that lie on its own surface
/// (same_surface); where none does (a surface narrower than the step, or an edge between
/// samples), the sample nearest it in depth. Wherever all four samples are fully lit the row
/// keeps its fill of 1 (most of a frame), as do open-water pixels.
void upsample_row(int W, int Wc, int step, float ty, const float* z, const float* va,
                  const float* vb, const float* za, const float* zb, float* out) {
    std::fill_n(out, W, 1.0f);
    const float inv = 1.0f / float(step);
    // Per column of samples, whether either row's sample there is not fully lit, then zeros
    // past the end: runs of fully lit spans are skipped eight at a time (most of a row that
    // holds a shadow; testing each span's four samples in turn cost more than the shadows).
    thread_local std::vector<unsigned char> buffer;
    buffer.assign(std::size_t(Wc) + 16, 0);
    unsigned char* dark = buffer.data();
    for (int i = 0; i < Wc; ++i)  // (no && : a branch-free loop, vectorised)
        dark[i] = static_cast<unsigned char>(int(!(va[i] >= 1.0f)) | int(!(vb[i] >= 1.0f)));
    for (int i0 = 0; i0 < Wc; ++i0) {
        std::uint64_t run;  // spans i0 .. i0 + 7 read samples i0 .. i0 + 8
        std::memcpy(&run, dark + i0, sizeof run);
        if (run == 0 && dark[i0 + 8] == 0) {
            i0 += 7;
            continue;
        }
        const int i1 = std::min(i0 + 1, Wc - 1);
        if (!dark[i0] && !dark[i1]) continue;
        const float vk[4] = {va[i0], va[i1], vb[i0], vb[i1]};
        const float zk[4] = {za[i0 * step], za[i1 * step], zb[i0 * step], zb[i1 * step]};
        const int u_end = std::min(W, (i0 + 1) * step);
        for (int u = i0 * step; u < u_end; ++u) {
            const float zp = z[u];
            if (!has_surface(zp)) continue;
            const float tx = float(u - i0 * step) * inv;
            const float wk[4] = {(1.0f - tx) * (1.0f - ty), tx * (1.0f - ty), (1.0f - tx) * ty,
                                 tx * ty};
            float sum = 0.0f, acc = 0.0f, nearest = 1.0f, best = INFINITY;
            for (int k = 0; k < 4; ++k) {
                if (!has_surface(zk[k])) continue;
                const float dz = std::fabs(zk[k] - zp);
                if (dz < best) best = dz, nearest = vk[k];
                if (same_surface(zp, zk[k])) sum += wk[k], acc += wk[k] * vk[k];
            }
            out[u] = sum > 0.0f ? acc / sum : nearest;
        }
    }
}

/// Whether every value of a visibility row is 1 (fully lit).
DEEPSEA_CLONES
bool all_lit(const float* v, int n) {
    int shaded = 0;  // (an integer reduction: vectorised without -ffast-math)
    for (int i = 0; i < n; ++i) shaded |= v[i] < 1.0f ? 1 : 0;
    return shaded == 0;
}

}  // namespace

void LampShadows::compute(const Camera& cam, const Image& zdepth, const Rig& rig,
                          const ShadowSettings& settings) {
    if (settings.step < 1) throw ConfigError("shadows: step must be >= 1 pixel");
    const float t = float(settings.thickness);
    const int s = settings.step;
    if (s == 1) {
        sweep(cam, rig, t, zdepth, 1);
        return;
    }
    const Camera cc = coarse_camera(cam, s);
    const int W = cam.width, H = cam.height, Wc = cc.width, Hc = cc.height;
    if (!m_coarse) m_coarse = std::make_unique<LampShadows>();
    m_coarse->sweep(cc, rig, t, zdepth, s);

    m_width = W;
    m_height = H;
    m_visibility.resize(rig.lights.size());
    m_ones.resize(rig.lights.size());
    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        Image& vis = m_visibility[l];
        std::vector<unsigned char>& ones = m_ones[l];
        if (vis.width != W || vis.height != H || vis.channels != 1) {
            vis = Image(W, H, 1);
            ones.clear();
        }
        ones.resize(std::size_t(H), 0);
        // Which coarse rows are fully lit (also kept for the coarse sweep's next fill).
        std::vector<unsigned char>& lit = m_coarse->m_ones[l];
        tbb::parallel_for(0, Hc,
                          [&](int j) { lit[std::size_t(j)] = all_lit(m_coarse->row(l, j), Wc); });
        // A row between two fully lit coarse rows (most of a frame) is all 1: filled where it
        // does not hold only 1 already.
        tbb::parallel_for(0, H, [&](int v) {
            const int j0 = v / s, j1 = std::min(j0 + 1, Hc - 1);
            if (lit[std::size_t(j0)] && lit[std::size_t(j1)]) {
                if (!ones[std::size_t(v)]) std::fill_n(vis.row(v), W, 1.0f);
                ones[std::size_t(v)] = 1;
                return;
            }
            const float ty = float(v - j0 * s) / float(s);
            upsample_row(W, Wc, s, ty, zdepth.row(v), m_coarse->row(l, j0), m_coarse->row(l, j1),
                         zdepth.row(j0 * s), zdepth.row(j1 * s), vis.row(v));
            ones[std::size_t(v)] = 0;
        });
    }
}

}  // namespace deepsea
