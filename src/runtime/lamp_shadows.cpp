// Lamp shadows by sweeping each lamp's epipolar lines (docs/model.md, "Lamp shadows").
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

namespace deepsea {

namespace {

/// One family of lines in image coordinates (a, b): (u, v), or (v, u) where `swap`.
struct Family {
    bool swap = false;
    bool radial = false;
    int sigma = 1;          ///< radial: the half (a - ea has this sign) the fan covers
    int dir = 1;            ///< the sweep's step along a
    double ea = 0, eb = 0;  ///< radial: the epipole
    double m = 1;           ///< radial: slope of line i is i / m
    double slope = 0;       ///< parallel: b = i + slope * a
    long i_min = 0, i_max = -1;
};

constexpr double kFarEpipole = 1e6;  // px from the image: lines taken as parallel beyond

long round_index(double x) { return long(std::floor(x + 0.5)); }

}  // namespace

struct LampShadows::Lines {
    std::vector<Family> families;
    int width = 0, height = 0;

    /// The family and line that pixel (u, v) belongs to.
    void locate(int u, int v, int& family, long& line) const {
        const Family& f0 = families[0];
        if (!f0.radial) {
            const double a = f0.swap ? v : u, b = f0.swap ? u : v;
            family = 0;
            line = round_index(b - f0.slope * a);
            return;
        }
        const double dx = u - (f0.swap ? f0.eb : f0.ea), dy = v - (f0.swap ? f0.ea : f0.eb);
        double qa, qb;
        if (dx >= std::fabs(dy)) {
            family = 0, qa = dx, qb = dy;
        } else if (-dx >= std::fabs(dy)) {
            family = 1, qa = dx, qb = dy;
        } else if (dy > 0) {
            family = 2, qa = dy, qb = dx;
        } else {
            family = 3, qa = dy, qb = dx;
        }
        line = qa == 0.0 ? 0 : round_index(families[family].m * qb / qa);
    }
    double line_b(const Family& f, long i, double a) const {
        return f.radial ? f.eb + (double(i) / f.m) * (a - f.ea) : double(i) + f.slope * a;
    }
};

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
        const double c[4] = {0.0, -f.slope * (A - 1), B - 1, B - 1 - f.slope * (A - 1)};
        f.i_min = round_index(*std::min_element(c, c + 4)) - 1;
        f.i_max = round_index(*std::max_element(c, c + 4)) + 1;
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

/// Per pixel of row v for the lamp at L (unit a, distance dl): the shadow coordinate of the
/// surface (gf), and, as an occluder, of its pixel's far edge along the sweep (gh) and of that
/// edge `thickness` deeper (gb), -FLT_MAX for open water; the penumbra's scale k and the lamp
/// distance d1. The edge is half a pixel further along the sweep, whose direction at (u, v) is
/// (u - ex, v - ey) times `outward` (radial lines) or (ex, ey) (parallel lines), scaled so
/// that its larger component is 1/2: where a pixel's surface ends is unknown, and between two
/// pixels is the least biased guess (without it every shadow edge lay half a pixel short).
DEEPSEA_CLONES
void shadow_row(int n, const float* __restrict z, const float* __restrict rx, float ry, float fx,
                float fy, int v, bool radial, float ex, float ey, float outward, float ax, float ay,
                float az, float dl, float lx, float ly, float lz, float t, float* __restrict gf,
                float* __restrict gh, float* __restrict gb, float* __restrict k,
                float* __restrict d1) {
#pragma omp simd
    for (int u = 0; u < n; ++u) {
        const bool surf = z[u] > 0.0f;
        const float zs = surf ? z[u] : 1.0f;
        const float px = rx[u] * zs, py = ry * zs;
        const float cx = py * az - zs * ay, cy = zs * ax - px * az, cz = px * ay - py * ax;
        const float c2 = std::max(cx * cx + cy * cy + cz * cz, 1e-30f);
        const float pa = px * ax + py * ay + zs * az;
        const float dx = lx - px, dy = ly - py, dz = lz - zs;
        const float d = std::sqrt(dx * dx + dy * dy + dz * dz);
        gf[u] = surf ? (dl - pa) / std::sqrt(c2) : -FLT_MAX;
        k[u] = c2 / d;
        d1[u] = d;
        // the pixel's far edge
        const float su = radial ? outward * (float(u) - ex) : ex;
        const float sv = radial ? outward * (float(v) - ey) : ey;
        const float m = std::max(std::max(std::fabs(su), std::fabs(sv)), 1e-20f);
        const float qx = (rx[u] + 0.5f * su / (m * fx)) * zs, qy = (ry + 0.5f * sv / (m * fy)) * zs;
        const float ex2 = qy * az - zs * ay, ey2 = zs * ax - qx * az, ez2 = qx * ay - qy * ax;
        const float e2 = std::max(ex2 * ex2 + ey2 * ey2 + ez2 * ez2, 1e-30f);
        const float qa = qx * ax + qy * ay + zs * az;
        const float inv = 1.0f / std::sqrt(e2);
        // deeper by t along the viewing ray: Q (z + t) / z, so Q x a and Q . a scale alike
        const float s = (zs + t) / zs;
        gh[u] = surf ? (dl - qa) * inv : -FLT_MAX;
        gb[u] = surf ? (dl - s * qa) * inv / s : -FLT_MAX;
    }
}

/// A line's running horizon: the interval [lo, g] of shadow coordinates that the seen surfaces
/// swept so far block, the pixel q whose surface is its upper edge (-1: none yet), that edge's
/// coordinate g and the step kq where it was swept. q2 (coordinate g2) is the edge before it,
/// where q continues a lit surface from it (the lit side of a penumbra, where the lit surface
/// itself is already the highest).
struct Horizon {
    float g = -FLT_MAX, lo = FLT_MAX, g2 = -FLT_MAX;
    long q = -1, q2 = -1;
    int kq = 0;
};

}  // namespace

LampShadows::LampShadows() = default;
LampShadows::~LampShadows() = default;
LampShadows::LampShadows(LampShadows&&) noexcept = default;
LampShadows& LampShadows::operator=(LampShadows&&) noexcept = default;

void LampShadows::compute(const Camera& cam, const Image& zdepth, const Rig& rig,
                          const ShadowSettings& settings) {
    const int W = cam.width, H = cam.height;
    const std::size_t N = std::size_t(W) * H;
    m_width = W;
    m_height = H;
    std::vector<Vec3> positions;
    for (const Light& l : rig.lights) positions.push_back(l.position);
    if (!(m_camera == cam) || positions.size() != m_positions.size() ||
        !std::equal(
            positions.begin(), positions.end(), m_positions.begin(),
            [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; })) {
        m_lines.clear();
        for (const Vec3& p : positions) m_lines.push_back(make_lines(cam, p));
        m_camera = cam;
        m_positions = positions;
        m_rx.resize(W);
        m_ry.resize(H);
        for (int u = 0; u < W; ++u) m_rx[u] = float(cam.ray_x(u));
        for (int v = 0; v < H; ++v) m_ry[v] = float(cam.ray_y(v));
    }
    m_visibility.resize(rig.lights.size());
    for (auto* a : {&m_gf, &m_gh, &m_gb, &m_k, &m_d1}) a->resize(N);
    const float t = float(settings.thickness);
    thread_local std::vector<float> zrow;

    for (std::size_t l = 0; l < rig.lights.size(); ++l) {
        const Vec3& L = rig.lights[l].position;
        const double dl = length(L);
        const Vec3 a = L * (1.0 / dl);
        const float R = float(rig.lights[l].radius);
        Image& vis = m_visibility[l];
        if (vis.width != W || vis.height != H || vis.channels != 1) vis = Image(W, H, 1);
        const Lines& lines = m_lines[l];
        const Family& f0 = lines.families[0];
        const float ex = float(f0.swap ? f0.eb : f0.ea), ey = float(f0.swap ? f0.ea : f0.eb);
        const float outward = float(f0.dir * f0.sigma);  // radial: 1 away from the epipole
        const float px = float(f0.swap ? f0.slope * f0.dir : f0.dir);
        const float py = float(f0.swap ? f0.dir : f0.slope * f0.dir);
        tbb::parallel_for(0, H, [&](int v) {
            zrow.resize(W);
            const float* raw = zdepth.row(v);
            for (int u = 0; u < W; ++u) zrow[u] = has_surface(raw[u]) ? raw[u] : 0.0f;
            const std::size_t o = std::size_t(v) * W;
            shadow_row(W, zrow.data(), m_rx.data(), m_ry[v], float(cam.fx), float(cam.fy), v,
                       f0.radial, f0.radial ? ex : px, f0.radial ? ey : py, outward, float(a.x),
                       float(a.y), float(a.z), float(dl), float(L.x), float(L.y), float(L.z), t,
                       m_gf.data() + o, m_gh.data() + o, m_gb.data() + o, m_k.data() + o,
                       m_d1.data() + o);
            std::fill_n(vis.row(v), W, 1.0f);
        });

        // P's visibility under the horizon h (pixel p at (u, v)).
        // The penumbra's argument at P (pixel p at (u, v), shadow coordinate gp) of the edge q.
        auto argument = [&](long p, int u, int v, float gp, long q, float gq) -> float {
            const float delta = gp - gq;
            const int uq = int(q % W), vq = int(q / W);
            const float zp = zdepth.at(u, v), zq = zdepth.at(uq, vq);
            const float dx = m_rx[u] * zp - m_rx[uq] * zq, dy = m_ry[v] * zp - m_ry[vq] * zq,
                        dz = zp - zq;
            const float d_o = std::sqrt(dx * dx + dy * dy + dz * dz);
            if (!(d_o > 0.0f)) return delta > 0.0f ? 1.0f : -1.0f;
            return penumbra_argument(delta, m_k[p], d_o, m_d1[q], R);
        };
        // P's visibility under the horizon h.
        auto visible = [&](long p, int u, int v, const Horizon& h) -> float {
            const float gp = m_gf[p];
            if (gp == -FLT_MAX || h.q < 0 || gp < h.lo) return 1.0f;
            if (!(R > 0.0f)) return gp > h.g ? 1.0f : 0.0f;
            float arg = argument(p, u, v, gp, h.q, h.g);
            if (h.q2 >= 0) arg = std::min(arg, argument(p, u, v, gp, h.q2, h.g2));
            return disc_visible_fraction(arg);
        };
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
                // the state two columns back: a pixel is never its own or its neighbour's
                // horizon (the sample nearest the line may lie half a pixel beside it)
                // The horizon holds the samples up to two columns back (past, when column k
                // is evaluated): a pixel is never its own or its neighbour's horizon (the
                // sample nearest the line may lie half a pixel beside it). A sample's edge
                // toward the next one along the line is their chord's midpoint on one surface
                // (mean shadow coordinate: chords of a convex surface lie inside it, so a lit
                // surface never shades itself), else its pixel's far edge at its own depth.
                Horizon h;
                long prev = -1;  // the last column's sample (-1: none or open water)
                for (int k = 0; k < count; ++k) {
                    const int a = first + k * step;
                    const double b = lines.line_b(f, i, a);
                    const bool inside = b >= -1.0 && b <= double(B);
                    const int r0 = int(std::floor(b + 0.5));
                    long q = -1;
                    if (inside && r0 >= 0 && r0 < B) {
                        q = f.swap ? long(a) * W + r0 : long(r0) * W + a;
                        if (m_gf[q] == -FLT_MAX) q = -1;
                    }
                    const Horizon past = h;
                    if (prev >= 0) {
                        const bool chord =
                            q >= 0 && same_surface(zdepth.data[q], zdepth.data[prev]);
                        const float ge = chord ? 0.5f * (m_gf[prev] + m_gf[q]) : m_gh[prev];
                        const float gb = m_gb[prev];
                        if (ge > h.g) {
                            h.lo = gb <= h.g ? std::min(h.lo, gb) : gb;
                            // a lit surface going on from the edge keeps the edge as q2
                            const bool goes_on = h.q >= 0 && k - 1 - h.kq <= 2 &&
                                                 same_surface(zdepth.data[prev], zdepth.data[h.q]);
                            if (!goes_on) {
                                h.q2 = h.q;
                                h.g2 = h.g;
                            }
                            h.g = ge;
                            h.q = prev;
                            h.kq = k - 1;
                        } else if (ge >= h.lo) {
                            h.lo = std::min(h.lo, gb);
                        }
                    }
                    prev = q;
                    if (!inside) continue;
                    const int bf = int(std::floor(b));
                    for (int r = bf; r <= bf + 1; ++r) {
                        if (r < 0 || r >= B) continue;
                        const int u = f.swap ? r : a, v = f.swap ? a : r;
                        int fam;
                        long li;
                        lines.locate(u, v, fam, li);
                        if (fam != int(fi) || li != i) continue;
                        vis.row(v)[u] = visible(long(v) * W + u, u, v, past);
                    }
                }
            });
        }
    }
}

}  // namespace deepsea
