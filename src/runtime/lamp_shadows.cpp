// Lamp shadows by sweeping each lamp's epipolar lines (docs/snow-shadows.md, "Lamp shadows").
// Compiled with -ffast-math -fopenmp-simd (the per-pixel pass is vectorised): open water is
// marked with -FLT_MAX, never NaN or inf.
//
// A point P's segment to the lamp projects onto the image line from P's pixel toward the lamp's
// image (the epipole; for a lamp in the camera's plane z = 0, toward the lamp's side), and every
// camera ray that line crosses lies in P's epipolar plane. So the pixels between P and the
// epipole hold every seen surface that can shade P, and they come before P when a line is swept
// from the epipole outward. Lines: through a finite epipole, four fans (|slope| <= 1 about the
// image's x and y axes, 1 px apart where they leave the image); at infinity, parallel lines 1 px
// apart along the image's major axis. Each pixel belongs to the one line that locate() names and
// is written by that line only, so lines run in parallel and any thread count gives the same
// bits.

#include "deepsea/runtime/lamp_shadows.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "clones.h"
#include "deepsea/optics/normals.h"
#include "lamp_shadows_lines.h"

namespace deepsea {

namespace {

/// The lines of a lamp at L for the camera.
LampShadows::Lines make_lines(const Camera& cam, const Vec3& L) {
    LampShadows::Lines lines;
    lines.width = cam.width;
    lines.height = cam.height;
    const double W = cam.width, H = cam.height;
    // The lamp's image in homogeneous pixels; the sweep runs along p * Lz - eh (from the
    // lamp's side toward P).
    const double ehx = cam.fx * L.x + cam.cx * L.z, ehy = cam.fy * L.y + cam.cy * L.z;
    const double cu = 0.5 * (W - 1), cv = 0.5 * (H - 1);
    const bool finite = std::fabs(L.z) > 1e-12 * length(L) &&
                        std::hypot(ehx / L.z - cu, ehy / L.z - cv) < kFarEpipole;
    if (!finite) {
        const double dx = cu * L.z - ehx, dy = cv * L.z - ehy;
        Family f;
        f.swap = std::fabs(dy) > std::fabs(dx);
        const double da = f.swap ? dy : dx, db = f.swap ? dx : dy;
        f.dir = da > 0 ? 1 : -1;
        f.slope = db / da;
        const double A = f.swap ? H : W, B = f.swap ? W : H;
        // Exactly the lines that hold pixels (locate()'s b - slope a is extreme at a corner):
        // a line beside the image would be swept for nothing, in a block of lanes of its own
        // off the fast path.
        const double c[4] = {0.0, -f.slope * (A - 1), B - 1, B - 1 - f.slope * (A - 1)};
        f.i_min = round_index(*std::min_element(c, c + 4));
        f.i_max = round_index(*std::max_element(c, c + 4));
        lines.families.push_back(f);
        return lines;
    }
    const double ex = ehx / L.z, ey = ehy / L.z;
    const int outward = L.z > 0 ? 1 : -1;
    for (int k = 0; k < 4; ++k) {
        Family f;
        f.radial = true;
        f.swap = k >= 2;
        f.sigma = (k % 2 == 0) ? 1 : -1;
        f.dir = f.sigma * outward;
        f.ea = f.swap ? ey : ex;
        f.eb = f.swap ? ex : ey;
        // 1 px apart (less than) where the fan leaves the image: m > the farthest |a - ea|
        const double A = f.swap ? H : W;
        f.m = std::floor(std::max(std::fabs(f.ea), std::fabs(A - 1 - f.ea))) + 2.0;
        f.i_max = -1;
        f.i_min = 0;
        lines.families.push_back(f);
    }
    // Which lines hold pixels: once per camera and lamp, so simply every pixel.
    std::vector<long> lo(4, 1L << 40), hi(4, -(1L << 40));
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            int fam;
            long i;
            lines.locate(u, v, fam, i);
            lo[fam] = std::min(lo[fam], i);
            hi[fam] = std::max(hi[fam], i);
        }
    }
    for (int k = 0; k < 4; ++k) {
        lines.families[k].i_min = lo[k];
        lines.families[k].i_max = hi[k];
    }
    return lines;
}

/// Per pixel of row v: sample_terms (lamp_shadows_lines.h) along the row.
DEEPSEA_CLONES
void shadow_row(int n, int v, const float* __restrict z, const float* __restrict rx, float ry,
                const RowParams& prm, float* __restrict gf, float* __restrict gh,
                float* __restrict gb, float* __restrict k, float* __restrict d1) {
    // the sweep's direction at (u, v): (au u + bu, sv) (a select on `radial` in the loop kept
    // GCC from vectorising it)
    const float au = prm.radial ? prm.outward : 0.0f;
    const float bu = prm.radial ? -prm.outward * prm.ex : prm.ex;
    const float sv = prm.radial ? prm.outward * (float(v) - prm.ey) : prm.ey;
    const RowParams p = prm;  // (a copy: loop invariants the vectoriser can see as such)
#pragma omp simd
    for (int u = 0; u < n; ++u)
        sample_terms(z[u], rx[u], ry, au * float(u) + bu, sv, p, gf[u], gh[u], gb[u], k[u], d1[u]);
}

/// An occluder's edge: its shadow coordinate g, position and distance to the lamp s_l.
struct Edge {
    float g = -FLT_MAX, x = 0, y = 0, z = 0, s_l = 0;
};

/// A line's running horizon: the interval [lo, e.g] of shadow coordinates that the seen
/// surfaces swept so far block, with e its upper edge (q its pixel, -1: none yet; kq the step
/// where it was swept). e2 (valid where q2 >= 0) is the edge before it, where e continues a lit
/// surface from it (the lit side of a penumbra, where the lit surface is already the highest).
struct Horizon {
    Edge e, e2;
    float lo = FLT_MAX;
    long q = -1, q2 = -1;
    int kq = 0;
};

/// The penumbra's argument at P (position p, shadow coordinate gp, scale k) of the edge e, or
/// 1 where it is at least 1 (the whole disc is seen past that edge: no square root).
inline float penumbra_at(float gp, float k, float px, float py, float pz, const Edge& e, float R) {
    const float delta = gp - e.g;
    const float dx = px - e.x, dy = py - e.y, dz = pz - e.z;
    const float d2 = dx * dx + dy * dy + dz * dz;
    const float num = delta * k * e.s_l;  // h = num / (R d_o)
    if (num > 0.0f && num * num >= R * R * d2) return 1.0f;
    if (!(d2 > 0.0f)) return delta > 0.0f ? 1.0f : -1.0f;
    return num / (R * std::sqrt(d2));
}

/// One lamp's per-pixel inputs and output, as raw pointers (what the line loops read).
struct Sweep {
    const float *gf, *gh, *gb, *k, *d1, *z, *rx, *ry;
    float* out;
    int W;
    float R;

    /// P's visibility under the horizon h (pixel p at (u, v)).
    float visible(long p, int u, int v, const Horizon& h) const {
        const float gp = gf[p];
        if (gp == -FLT_MAX || h.q < 0 || gp < h.lo) return 1.0f;
        if (!(R > 0.0f)) return gp > h.e.g ? 1.0f : 0.0f;
        const float zp = z[p], px = rx[u] * zp, py = ry[v] * zp;
        float arg = penumbra_at(gp, k[p], px, py, zp, h.e, R);
        if (h.q2 >= 0 && arg > -1.0f)
            arg = std::min(arg, penumbra_at(gp, k[p], px, py, zp, h.e2, R));
        return arg >= 1.0f ? 1.0f : disc_visible_fraction(arg);
    }

    /// Adds the sample `prev` (pixel (u, v), swept at step kp; -1: none) to the horizon, its
    /// edge toward the next sample q (-1: none or open water). A sample's edge is their chord's
    /// midpoint on one surface (mean shadow coordinate: chords of a convex surface lie inside
    /// it, so a lit surface never shades itself), else its pixel's far edge at its own depth.
    void take(Horizon& h, long prev, int u, int v, int kp, long q) const {
        if (prev < 0) return;
        const float zq = z[prev];
        const bool chord = q >= 0 && same_surface(z[q], zq);
        const float ge = chord ? 0.5f * (gf[prev] + gf[q]) : gh[prev];
        const float b = gb[prev];
        if (ge > h.e.g) {
            h.lo = b <= h.e.g ? std::min(h.lo, b) : b;
            // a lit surface going on from the edge keeps the edge as e2
            const bool goes_on = h.q >= 0 && kp - h.kq <= 2 && same_surface(zq, z[h.q]);
            if (!goes_on) {
                h.e2 = h.e;
                h.q2 = h.q;
            }
            h.e = Edge{ge, rx[u] * zq, ry[v] * zq, zq, d1[prev]};
            h.q = prev;
            h.kq = kp;
        } else if (ge >= h.lo) {
            h.lo = std::min(h.lo, b);
        }
    }
};

/// The camera with its x and y axes exchanged: pixel (u, v) of the transposed image is pixel
/// (v, u) of `cam`'s.
Camera transposed(const Camera& cam) {
    Camera c;
    c.width = cam.height;
    c.height = cam.width;
    c.fx = cam.fy;
    c.fy = cam.fx;
    c.cx = cam.cy;
    c.cy = cam.cx;
    return c;
}

/// Every step-th pixel of src along each axis (w x h of them), into `sub` (row-major, w x h;
/// none where null) and `tr` (transposed, h x w: tr[u h + v] = src.row(v step)[u step]; none
/// where null), in one pass: in tiles of kTile rows, so that the rows read stay in the cache
/// while tr's rows are written.
void subsample(const Image& src, int step, int w, int h, float* sub, float* tr) {
    constexpr int kTile = 32;
    tbb::parallel_for(0, (h + kTile - 1) / kTile, [&](int tv) {
        const int v0 = tv * kTile, n = std::min(h, v0 + kTile) - v0;
        const float* rows[kTile];
        for (int k = 0; k < n; ++k) rows[k] = src.row((v0 + k) * step);
        if (sub) {
            for (int k = 0; k < n; ++k) {
                float* out = sub + std::size_t(v0 + k) * w;
                const float* in = rows[k];
                for (int u = 0; u < w; ++u) out[u] = in[std::size_t(u) * step];
            }
        }
        if (!tr) return;
        for (int u = 0; u < w; ++u) {
            float* out = tr + std::size_t(u) * h + v0;
            const std::size_t x = std::size_t(u) * step;
            for (int k = 0; k < n; ++k) out[k] = rows[k][x];
        }
    });
}

}  // namespace

LampShadows::LampShadows() = default;
LampShadows::~LampShadows() = default;
LampShadows::LampShadows(LampShadows&&) noexcept = default;
LampShadows& LampShadows::operator=(LampShadows&&) noexcept = default;

void LampShadows::sweep(const Camera& cam, const Rig& rig, float thickness, const Image& frame,
                        int step) {
    const int W = cam.width, H = cam.height;
    const std::size_t N = std::size_t(W) * H;
    m_width = W;
    m_height = H;
    std::vector<Vec3> positions;
    for (const Light& l : rig.lights) positions.push_back(l.position);
    const Camera camt = transposed(cam);
    if (!(m_camera == cam) || positions.size() != m_positions.size() ||
        !std::equal(
            positions.begin(), positions.end(), m_positions.begin(),
            [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; })) {
        m_lines.clear();
        m_lines_t.clear();
        for (const Vec3& p : positions) {
            m_lines.push_back(make_lines(cam, p));
            // Parallel lines along image rows are swept in the transposed image, where they
            // are columns: the lanes' eight lines then lie side by side in memory.
            const Family& f = m_lines.back().families[0];
            Lines t;
            if (!f.radial && !f.swap) {
                t = make_lines(camt, Vec3{p.y, p.x, p.z});
                if (t.families[0].radial || !t.families[0].swap) t = Lines{};
            }
            m_lines_t.push_back(std::move(t));
        }
        m_camera = cam;
        m_positions = positions;
        m_rx.resize(W);
        m_ry.resize(H);
        for (int u = 0; u < W; ++u) m_rx[u] = float(cam.ray_x(u));
        for (int v = 0; v < H; ++v) m_ry[v] = float(cam.ray_y(v));
    }
    // The depth swept (every step-th pixel's) where a lamp is swept in the frame itself and,
    // where one is swept in the transposed frame, its transpose: in one pass. (With the demo's
    // lamps, both swept transposed, the subsample is not written: the upsampling reads the
    // samples' depths from the frame.)
    bool transposed = false, direct = false, radial = false;
    for (std::size_t l = 0; l < m_lines.size(); ++l) {
        const bool t = !m_lines_t[l].families.empty();
        transposed |= t;
        direct |= !t;
        radial |= !t && m_lines[l].families[0].radial;
    }
    const bool sub = step > 1 && direct;
    if (sub && (m_sub.width != W || m_sub.height != H)) m_sub = Image(W, H, 1);
    if (transposed && (m_depth_t.width != H || m_depth_t.height != W)) m_depth_t = Image(H, W, 1);
    if (sub || transposed)
        subsample(frame, step, W, H, sub ? m_sub.data.data() : nullptr,
                  transposed ? m_depth_t.data.data() : nullptr);
    const Image& zdepth = step > 1 ? m_sub : frame;
    m_visibility.resize(rig.lights.size());
    m_ones.resize(rig.lights.size());
    // the per-pixel terms of the scalar sweep (radial lines only)
    if (radial)
        for (auto* a : {&m_gf, &m_gh, &m_gb, &m_k, &m_d1}) a->resize(N);
    std::vector<ParallelSweep> parallel;  // (swept after the loop, every lamp's at once)
    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        const Vec3& L = rig.lights[l].position;
        const float R = float(rig.lights[l].radius);
        Image& vis = m_visibility[l];
        std::vector<unsigned char>& ones = m_ones[l];
        if (vis.width != W || vis.height != H || vis.channels != 1) {
            vis = Image(W, H, 1);
            ones.clear();
        }
        ones.resize(std::size_t(H), 0);
        if (m_lines_t[l].families.empty()) {
            lamp_pass(cam, zdepth, L, R, m_lines[l], m_rx.data(), m_ry.data(), thickness, vis,
                      ones.data(), parallel);
            std::fill(ones.begin(), ones.end(), 0);  // (not known after the sweep)
            continue;
        }
        lamp_pass(camt, m_depth_t, Vec3{L.y, L.x, L.z}, R, m_lines_t[l], m_ry.data(), m_rx.data(),
                  thickness, vis, ones.data(), parallel);
        std::fill(ones.begin(), ones.end(), 0);
    }
    sweep_parallel_lines(parallel);
}

void LampShadows::lamp_pass(const Camera& cam, const Image& zdepth, const Vec3& L, float R,
                            const Lines& lines, const float* rx, const float* ry, float t,
                            Image& vis, const unsigned char* ones,
                            std::vector<ParallelSweep>& parallel) {
    const int W = cam.width, H = cam.height;
    thread_local std::vector<float> zrow;
    {
        const double dl = length(L);
        const Vec3 a = L * (1.0 / dl);
        const Family& f0 = lines.families[0];
        const float ex = float(f0.swap ? f0.eb : f0.ea), ey = float(f0.swap ? f0.ea : f0.eb);
        const float outward = float(f0.dir * f0.sigma);  // radial: 1 away from the epipole
        const float px = float(f0.swap ? f0.slope * f0.dir : f0.dir);
        const float py = float(f0.swap ? f0.dir : f0.slope * f0.dir);
        const RowParams prm{float(cam.fx),
                            float(cam.fy),
                            f0.radial ? ex : px,
                            f0.radial ? ey : py,
                            outward,
                            float(a.x),
                            float(a.y),
                            float(a.z),
                            float(dl),
                            float(L.x),
                            float(L.y),
                            float(L.z),
                            t,
                            f0.radial};
        if (!f0.radial) {
            // parallel lines: sixteen at a time in vector lanes, each sample's terms computed
            // there (lamp_shadows_lanes.cpp), swept with the other lamps' after the loop
            // (vis is the frame's, this image's transpose where their sizes differ)
            tbb::parallel_for(0, vis.height, [&](int v) {
                if (!ones[v]) std::fill_n(vis.row(v), vis.width, 1.0f);
            });
            parallel.push_back(
                ParallelSweep{f0, SweepArrays{zdepth.data.data(), rx, ry, vis.data.data(), W, H, R,
                                              prm, vis.width != W}});
            return;
        }
        tbb::parallel_for(0, H, [&](int v) {
            zrow.resize(W);
            const float* raw = zdepth.row(v);
            for (int u = 0; u < W; ++u) zrow[u] = has_surface(raw[u]) ? raw[u] : 0.0f;
            const std::size_t o = std::size_t(v) * W;
            shadow_row(W, v, zrow.data(), rx, ry[v], prm, m_gf.data() + o, m_gh.data() + o,
                       m_gb.data() + o, m_k.data() + o, m_d1.data() + o);
            if (!ones[v]) std::fill_n(vis.row(v), W, 1.0f);
        });

        // open water keeps the fill's 1 (the sweep writes surfaces only)
        const Sweep sw{m_gf.data(),
                       m_gh.data(),
                       m_gb.data(),
                       m_k.data(),
                       m_d1.data(),
                       zdepth.data.data(),
                       rx,
                       ry,
                       vis.data.data(),
                       W,
                       R};
        for (std::size_t fi = 0; fi < lines.families.size(); ++fi) {
            const Family& f = lines.families[fi];
            if (f.i_max < f.i_min) continue;
            const int A = f.swap ? H : W, B = f.swap ? W : H;
            tbb::parallel_for(f.i_min, f.i_max + 1, [&](long i) {
                // the columns a where the line is inside the image, in sweep order
                int a0 = 0, a1 = A - 1;
                if (f.radial) {
                    if (f.sigma > 0) a0 = std::max(a0, int(std::ceil(f.ea)));
                    if (f.sigma < 0) a1 = std::min(a1, int(std::floor(f.ea)));
                }
                if (a0 > a1) return;
                const int step = f.dir, first = step > 0 ? a0 : a1, count = a1 - a0 + 1;
                // Column k is evaluated before the sample of column k - 1 joins the horizon:
                // a pixel is never its own or its neighbour's horizon (the sample nearest the
                // line may lie half a pixel beside it).
                Horizon h;
                long prev = -1;  // the last column's sample (-1: none or open water)
                int prev_u = 0, prev_v = 0;
                for (int k = 0; k < count; ++k) {
                    const int a = first + k * step;
                    const double b = lines.line_b(f, i, a);
                    const bool inside = b >= -1.0 && b <= double(B);
                    const int r0 = int(std::floor(b + 0.5));
                    long q = -1;
                    const int qu = f.swap ? r0 : a, qv = f.swap ? a : r0;
                    if (inside && r0 >= 0 && r0 < B) {
                        q = long(qv) * W + qu;
                        if (sw.gf[q] == -FLT_MAX) q = -1;
                    }
                    if (inside) {
                        const int bf = int(std::floor(b));
                        for (int r = bf; r <= bf + 1; ++r) {
                            if (r < 0 || r >= B) continue;
                            const int u = f.swap ? r : a, v = f.swap ? a : r;
                            int fam;
                            long li;
                            lines.locate(u, v, fam, li);
                            if (fam != int(fi) || li != i) continue;
                            const long p = long(v) * W + u;
                            if (sw.gf[p] != -FLT_MAX) sw.out[p] = sw.visible(p, u, v, h);
                        }
                    }
                    sw.take(h, prev, prev_u, prev_v, k - 1, q);
                    prev = q;
                    prev_u = qu;
                    prev_v = qv;
                }
            });
        }
    }
}

}  // namespace deepsea
