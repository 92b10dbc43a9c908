// MarineSnow::draw: the particles of a frame placed with the surface's test (snow_place.h),
// lit in float rows (snow_light.h) and drawn into the image by bands of rows in parallel, each
// band taking its particles in id order, so that the image and the ids are the same at any
// thread count. With motion streaks each disc is swept along the particle's image motion over
// the exposure.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "clones.h"
#include "deepsea/runtime/marine_snow.h"
#include "deepsea/runtime/snow_light.h"
#include "snow_place.h"
#include "snow_splat.h"

namespace deepsea {

using namespace snow_splat;

namespace {

/// Particles a task lights and sets up at most (halving_blocks).
constexpr std::size_t kBlock = 1024;
/// Rows per band of the drawing pass.
constexpr int kBandRows = 16;
/// A streak's end whose particle lies nearer than this planar depth (metres) when the shutter
/// opens or closes is taken at the frame's own position instead (it would project off to
/// infinity).
constexpr double kStreakNearM = 0.01;
/// Columns a sub-pixel streak's row may touch at most: kMaxSnowStreakPx and its reach.
constexpr int kRowBuffer = int(kMaxSnowStreakPx) + 8;

/// The frame's outputs, shared by the bands (each writes only its rows).
struct Target {
    const Image& zdepth;
    Image& final;
    Image* snow;
    Image* ids;
    float* best;
    int W, H;

    /// Adds weight w of splat s's light to pixel (x, y), unless its surface is nearer.
    void add(const Splat& s, int x, int y, float w) const {
        const float z = zdepth.at(x, y);
        if (!open_water(z) && z <= s.z) return;
        const float e[3] = {s.energy[0] * w, s.energy[1] * w, s.energy[2] * w};
        float* f = final.row(y) + 3 * x;
        for (int c = 0; c < 3; ++c) f[c] += e[c];
        if (snow) {
            float* l = snow->row(y) + 3 * x;
            for (int c = 0; c < 3; ++c) l[c] += e[c];
        }
        if (ids) {
            float& b = best[std::size_t(y) * W + x];
            const float sum = e[0] + e[1] + e[2];
            if (sum > b) {
                b = sum;
                ids->at(x, y) = float(s.id);
            }
        }
    }

    /// Reads rows y0..y1 of the depth and final images in order, a value per cache line: a
    /// dense band's particles then find their pixels in the cache (sequential reads stream at
    /// the memory's bandwidth; scattered ones each wait for memory).
    float warm(int y0, int y1, bool with_final) const {
        float sink = 0.0f;
        for (int y = y0; y <= y1; ++y) {
            const float* d = zdepth.row(y);
            for (int x = 0; x < W; x += 16) sink += d[x];
            if (!with_final) continue;
            const float* f = final.row(y);
            for (int x = 0; x < 3 * W; x += 16) sink += f[x];
        }
        return sink;
    }

    /// add() for `final` alone (a surface nearer than the particle: z > 0 and z <= s.z, s.z
    /// being finite, is add()'s test).
    template <class S>
    static void put(const S& s, float* f, float z, float wt) {
        if (!(wt > 0.0f) || (z > 0.0f && z <= s.z)) return;
        f[0] += s.energy[0] * wt;
        f[1] += s.energy[1] * wt;
        f[2] += s.energy[2] * wt;
    }

    /// Draws the rows y0..y1 of splat s.
    void draw(const Splat& s, int y0, int y1) const {
        const Window w = window(s);
        y0 = std::max(y0, std::max(w.va, 0));
        y1 = std::min(y1, std::min(w.vb, H - 1));
        const int x0 = std::max(w.ua, 0), x1 = std::min(w.ub, W - 1);
        if (s.len > 0.0f && s.radius <= 0.5f) {
            // Sub-pixel: the bilinear splats of the samples, summed per pixel first (so that
            // the id compares a particle's whole light there).
            float row[kRowBuffer];
            for (int y = y0; y <= y1; ++y) {
                const RowSpan r = row_span(s, y);
                const int ca = r.ca, cb = r.cb;
                if (ca > cb || cb - ca >= kRowBuffer) continue;
                std::fill(row, row + (cb - ca + 1), 0.0f);
                const float step = s.len / float(s.n);
                // The samples within a pixel of the row (a step's margin for rounding).
                const int k0 = std::max(0, ifloor(r.t0 / step - 0.5f) - 1);
                const int k1 = std::min(s.n - 1, iceil(r.t1 / step - 0.5f) + 1);
                for (int k = k0; k <= k1; ++k) {
                    const float t = (float(k) + 0.5f) * step;
                    const float sv = s.ay + t * s.dy, fy = sv - float(ifloor(sv));
                    const int ky = ifloor(sv);
                    if (ky != y && ky + 1 != y) continue;
                    const float wy = ky == y ? 1.0f - fy : fy;
                    const float su = s.ax + t * s.dx, fx = su - float(ifloor(su));
                    const int kx = ifloor(su) - ca;
                    if (kx < 0 || kx + 1 > cb - ca) continue;  // rounding at the row's ends
                    row[kx] += wy * (1.0f - fx);
                    row[kx + 1] += wy * fx;
                }
                for (int x = std::max(ca, x0); x <= std::min(cb, x1); ++x)
                    if (row[x - ca] > 0.0f) add(s, x, y, row[x - ca] * s.inv_cover);
            }
            return;
        }
        if (s.len > 0.0f) {
            for (int y = y0; y <= y1; ++y) {
                const RowSpan r = row_span(s, y);
                for (int x = std::max(r.ca, x0); x <= std::min(r.cb, x1); ++x) {
                    const float c = sweep(s, x, y) * s.inv_cover;
                    if (c > 0.0f) add(s, x, y, c);
                }
            }
            return;
        }
        if (s.radius <= 0.5f) {
            // A particle smaller than a pixel: its light shared bilinearly by four pixels.
            // (with `final` alone, dot())
            const float fu = s.u - float(w.ua), fv = s.v - float(w.va);
            for (int y = y0; y <= y1; ++y) {
                const float wy = y == w.va ? 1.0f - fv : fv;
                for (int x = x0; x <= x1; ++x) {
                    const float wx = x == w.ua ? 1.0f - fu : fu;
                    if (wx * wy > 0.0f) add(s, x, y, wx * wy);
                }
            }
            return;
        }
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                const float c = coverage(s.u, s.v, s.radius, x, y) * s.inv_cover;
                if (c > 0.0f) add(s, x, y, c);
            }
    }
};

/// draw() of a still sub-pixel splat (s.dot) into `final` alone, rows y0..y1 of a band: the same
/// steps and sums, its window's two columns and rows written out. The images' pixels (z: depth,
/// W a row; f: final, 3 W a row) are the band's locals, not read from the images per particle.
inline void dot(const DotEntry& s, const float* z, float* f, int W, int H, int y0, int y1) {
    const int xa = s.ua, ya = s.va;
    const float fu = s.u - float(xa), fv = s.v - float(ya);
    const int ylo = std::max(std::max(y0, ya), 0), yhi = std::min(std::min(y1, ya + 1), H - 1);
    const bool left = xa >= 0, right = xa + 1 < W;
    for (int y = ylo; y <= yhi; ++y) {
        const float wy = y == ya ? 1.0f - fv : fv;
        const float* d = z + std::size_t(y) * std::size_t(W);
        float* out = f + std::size_t(y) * std::size_t(3 * W);
        if (left) Target::put(s, out + 3 * xa, d[xa], (1.0f - fu) * wy);
        if (right) Target::put(s, out + 3 * (xa + 1), d[xa + 1], fu * wy);
    }
}

/// Sets splat s's streak for the particle at camera-frame X (pose `pose`), seen at pixel
/// (u, v): from where it is seen when the shutter opens to where it is seen when it closes.
void set_streak(Splat& s, const Camera& cam, const CameraPose& pose, const Shutter& shutter,
                const Vec3& X, double u, double v) {
    const Vec3 world = to_world(pose, X);
    const auto seen = [&](const CameraPose& p, double& pu, double& pv) {
        const Vec3 Y = to_camera(p, world);
        pu = u;
        pv = v;
        if (!(Y.z >= kStreakNearM)) return;
        pu = cam.fx * Y.x / Y.z + cam.cx;
        pv = cam.fy * Y.y / Y.z + cam.cy;
    };
    double ou, ov, cu, cv;
    seen(shutter.open, ou, ov);
    seen(shutter.close, cu, cv);
    const double ex = cu - ou, ey = cv - ov, len = std::hypot(ex, ey);
    if (!(len >= kMinSnowStreakPx)) return;  // drawn as the still disc
    const double kept = std::min(len, kMaxSnowStreakPx);
    // Shortened about its middle where over the cap.
    const double shift = 0.5 * (len - kept) / len;
    s.ax = float(ou + ex * shift);
    s.ay = float(ov + ey * shift);
    s.dx = float(ex / len);
    s.dy = float(ey / len);
    s.len = float(kept);
    // A sub-pixel particle: bilinear splats at most half a pixel apart, each reaching a
    // pixel; a wider disc: its coverage swept, reaching R + 1/2.
    s.n = int(std::ceil(2.0 * kept));
    s.rh = s.radius <= 0.5f ? 1.0f : s.radius + 0.5f;
}

/// The rows of particles pt[0..m): the light's (x, y, z, 1 / |X|, D, snow_light.h) and each
/// disc's pixel (u, v) and radius. The same double arithmetic as snow_disc_radius_px and the
/// projection, in the same order, over four particles at a time (AVX2 without fused
/// multiply-adds, no fast-math: every value rounds as the scalar code's did, so the image is the
/// same bit for bit), the particles' fields copied into columns first (GCC does not vectorise
/// the loads from the 40-byte records).
DEEPSEA_CLONES_NO_FMA
void particle_rows(const SnowParticle* pt, int m, const Camera& cam, const ThinLens& lens, float* x,
                   float* y, float* z, float* inv_d2, float* D, float* u, float* v, float* radius) {
    const Camera c = cam;  // (copies: the stores below cannot change them)
    const ThinLens l = lens;
    constexpr int kChunk = 256;
    alignas(32) double cx[kChunk], cy[kChunk], cz[kChunk], cd[kChunk];
    for (int q0 = 0; q0 < m; q0 += kChunk) {
        const int k = std::min(kChunk, m - q0);
        for (int q = 0; q < k; ++q) {
            cx[q] = pt[q0 + q].position.x;
            cy[q] = pt[q0 + q].position.y;
            cz[q] = pt[q0 + q].position.z;
            cd[q] = pt[q0 + q].diameter;
        }
#pragma omp simd
        for (int q = 0; q < k; ++q) {
            const Vec3 X{cx[q], cy[q], cz[q]};
            const int o = q0 + q;
            x[o] = float(X.x);
            y[o] = float(X.y);
            z[o] = float(X.z);
            inv_d2[o] = float(1.0 / length(X));
            D[o] = float(cd[q]);
            u[o] = float(c.fx * X.x / X.z + c.cx);
            v[o] = float(c.fy * X.y / X.z + c.cy);
            radius[o] = float(snow_disc_radius_px(c, l, X, cd[q]));
        }
    }
}

}  // namespace

/// MarineSnow::draw's buffers, kept from frame to frame.
struct SnowScratch {
    SnowPlacing placing;
    std::vector<SnowParticle> particles;
    std::vector<Splat> splats;
    std::vector<float> rows;        ///< the particles as float rows (snow_light.h)
    std::vector<float> best;        ///< per pixel, the largest contribution so far
    std::vector<std::size_t> ends;  ///< the chunks of particles (halving_blocks)
    /// per chunk: where each band's entries start in its list (bands + 1)
    std::vector<std::uint32_t> at;
    /// per chunk: its particles' band entries, band by band, each band's in id order
    std::vector<std::vector<DotEntry>> lists;
    std::vector<int> off_drawn, band_drawn;
    std::vector<float> sinks;
};

SnowScratchHolder::SnowScratchHolder() = default;
SnowScratchHolder::SnowScratchHolder(const SnowScratchHolder&) {}
SnowScratchHolder::~SnowScratchHolder() = default;

SnowScratch& SnowScratchHolder::get() const {
    if (!m_p) m_p = std::make_unique<SnowScratch>();
    return *m_p;
}

namespace {

/// The ends of the blocks of particles [0, n) is cut into, after 0 in `ends`: halves of halves
/// down to kBlock particles or fewer, as TBB's blocked_range splits a range. A particle's light
/// rounds by its place in its block (snow_light's vector loops end in a shorter epilogue), so
/// fixed blocks keep the image the same at any thread count.
void halving_blocks(std::size_t b, std::size_t e, std::vector<std::size_t>& ends) {
    if (e - b > kBlock) {
        const std::size_t m = b + (e - b) / 2;
        halving_blocks(b, m, ends);
        halving_blocks(m, e, ends);
        return;
    }
    ends.push_back(e);
}

/// v resized to n, its memory grown by a quarter more where it must grow (the particles'
/// number changes from frame to frame).
template <class T>
void fit(std::vector<T>& v, std::size_t n) {
    if (n > v.capacity()) v.reserve(n + n / 4);
    v.resize(n);
}

}  // namespace

void MarineSnow::draw(const Camera& cam, const Image& zdepth, Image& final, Image* snow,
                      Image* ids) const {
    SnowScratch& sc = m_scratch.get();
    // Particles behind the surface at their pixel are placed unsized (diameter 0) and drawn not.
    place_snow(m_settings, cam, m_key, m_pose, &zdepth, sc.placing, sc.particles);
    const std::vector<SnowParticle>& particles = sc.particles;
    const ThinLens lens{cam.fx, m_settings.pixel_pitch_um, m_settings.f_number,
                        m_settings.focus_distance_m};
    const int W = cam.width, H = cam.height;
    const std::size_t n = particles.size();
    const bool streaks = m_settings.streaks && m_pose && m_shutter;
    if (ids) sc.best.assign(std::size_t(W) * H, 0.0f);
    fit(sc.splats, n);
    std::vector<Splat>& splats = sc.splats;
    // Rows: x, y, z, 1/|X|, D, the three energies, five of scratch, u, v and the radius.
    fit(sc.rows, 16 * n);
    float* rows = sc.rows.data();
    // Each band's particles, in id order, by a counting sort within each chunk of particles
    // (halving_blocks) as it is set up (while its records are in the cache): the band draws the
    // chunks' lists in chunk order. A particle whose centre lies behind the surface at its
    // pixel was found as it was placed (no size, no disc) and joins no band.
    const int bands = (H + kBandRows - 1) / kBandRows;
    sc.ends.assign(1, 0);
    if (n > 0) halving_blocks(0, n, sc.ends);
    const std::size_t chunks = sc.ends.size() - 1, nb = std::size_t(bands);
    const auto off_image = [&](const Splat& s) { return s.vb < 0 || s.va > H - 1; };
    // Where neither the snow layer nor the ids are asked for, still sub-pixel particles take
    // the short path (dot()), their fields copied into the bands' entries; every other
    // entry names its splat.
    const bool final_only = !snow && !ids;
    sc.at.assign(chunks * (nb + 1), 0);
    sc.off_drawn.assign(chunks, 0);
    if (sc.lists.size() < chunks) sc.lists.resize(chunks);
    std::uint32_t* const at = sc.at.data();
    tbb::parallel_for(std::size_t(0), chunks, [&](std::size_t k) {
        const std::size_t b = sc.ends[k], m = sc.ends[k + 1] - b;
        float* x = rows + b;
        float* y = x + n;
        float* z = y + n;
        float* inv_d2 = z + n;
        float* D = inv_d2 + n;
        float* er = D + n;
        float* eg = er + n;
        float* eb = eg + n;
        const SnowLightScratch scratch{eb + n, eb + 2 * n, eb + 3 * n, eb + 4 * n, eb + 5 * n};
        float* pu = eb + 6 * n;
        float* pv = pu + n;
        float* radius = pv + n;
        particle_rows(particles.data() + b, int(m), cam, lens, x, y, z, inv_d2, D, pu, pv, radius);
        snow_light(m_rig, m_water, m_settings.snow, cam.fx, cam.fy,
                   ParticleRows{int(m), x, y, z, inv_d2, D}, er, eg, eb, scratch, m_scattered);
        // the chunk's entries in id order with their bands, counted per band (at[b + 1])
        struct Placed {
            DotEntry e;
            int ba, bb;
        };
        thread_local std::vector<Placed> placed;
        placed.clear();
        std::uint32_t* const start = at + k * (nb + 1);
        for (std::size_t q = 0; q < m; ++q) {
            const SnowParticle& pt = particles[b + q];
            const Vec3& X = pt.position;
            Splat& s = splats[b + q];
            s.id = 0;                          // not drawn
            if (pt.diameter == 0.0) continue;  // behind the surface at its pixel
            s.u = pu[q];
            s.v = pv[q];
            s.radius = radius[q];
            s.z = z[q];
            s.energy[0] = er[q];
            s.energy[1] = eg[q];
            s.energy[2] = eb[q];
            s.len = 0.0f;
            if (streaks)
                set_streak(s, cam, *m_pose, *m_shutter, X, cam.fx * X.x / X.z + cam.cx,
                           cam.fy * X.y / X.z + cam.cy);
            const Window w = window(s);
            s.ua = w.ua;
            s.va = w.va;
            s.vb = w.vb;
            s.ba = std::max(w.va, 0) / kBandRows;
            s.bb = std::min(w.vb, H - 1) / kBandRows;
            s.dot = s.len == 0.0f && s.radius <= 0.5f;
            s.inv_cover = 1.0f;
            if (s.len > 0.0f && s.radius <= 0.5f) {
                s.inv_cover = 1.0f / float(s.n);  // each sample's bilinear weights sum to 1
            } else if (s.len > 0.0f) {
                // Normalised over the streak: its light is the still disc's, spread.
                float total = 0.0f;
                for (int yy = w.va; yy <= w.vb; ++yy) {
                    const RowSpan r = row_span(s, yy);
                    for (int xx = r.ca; xx <= r.cb; ++xx) total += sweep(s, xx, yy);
                }
                if (!(total > 0.0f)) continue;
                s.inv_cover = 1.0f / total;
            } else if (s.radius > 0.5f) {
                // Normalised over the disc: the particle's light is spread, not multiplied.
                float total = 0.0f;
                for (int yy = w.va; yy <= w.vb; ++yy)
                    for (int xx = w.ua; xx <= w.ub; ++xx)
                        total += coverage(s.u, s.v, s.radius, xx, yy);
                if (!(total > 0.0f)) continue;
                s.inv_cover = 1.0f / total;
            }
            s.id = pt.id;
            if (off_image(s)) {  // (drawn, counted in `drawn`, in no band)
                ++sc.off_drawn[k];
                continue;
            }
            for (int band = s.ba; band <= s.bb; ++band) ++start[band + 1];
            placed.push_back(
                {final_only && s.dot
                     ? DotEntry{s.u, s.v, s.z, {s.energy[0], s.energy[1], s.energy[2]}, s.ua, s.va}
                     : DotEntry{0.0f, 0.0f, -1.0f, {0.0f, 0.0f, 0.0f}, int(b + q), 0},
                 s.ba, s.bb});
        }
        for (std::size_t band = 0; band < nb; ++band) start[band + 1] += start[band];
        thread_local std::vector<std::uint32_t> fill;
        fill.assign(start, start + nb);
        std::vector<DotEntry>& list = sc.lists[k];
        fit(list, start[nb]);
        for (const Placed& p : placed)
            for (int band = p.ba; band <= p.bb; ++band) list[fill[std::size_t(band)]++] = p.e;
    });

    int drawn = 0;  // (counted per band below, at each particle's first band)
    for (const int c : sc.off_drawn) drawn += c;
    sc.band_drawn.assign(nb, 0);
    sc.sinks.assign(nb, 0.0f);
    const Target target{zdepth, final, snow, ids, sc.best.data(), W, H};
    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const auto& range) {
        for (int b = range.begin(); b != range.end(); ++b) {
            const int y0 = b * kBandRows, y1 = std::min(H, y0 + kBandRows) - 1;
            const std::size_t band = std::size_t(b);
            std::int64_t entries = 0;
            for (std::size_t k = 0; k < chunks; ++k)
                entries += at[k * (nb + 1) + band + 1] - at[k * (nb + 1) + band];
            // Warm when the particles would touch most of the band's cache lines anyway.
            if (entries * 64 > std::int64_t(y1 - y0 + 1) * W)
                sc.sinks[band] = target.warm(y0, y1, true);
            int count = 0;
            const float* zpix = zdepth.data.data();
            float* fpix = final.data.data();
            for (std::size_t k = 0; k < chunks; ++k) {
                const DotEntry* list = sc.lists[k].data();
                const std::uint32_t i1 = at[k * (nb + 1) + band + 1];
                for (std::uint32_t i = at[k * (nb + 1) + band]; i < i1; ++i) {
                    const DotEntry& e = list[i];
                    if (e.z > 0.0f) {
                        count += std::max(e.va, 0) / kBandRows == b ? 1 : 0;  // its first band
                        dot(e, zpix, fpix, W, H, y0, y1);
                        continue;
                    }
                    const Splat& s = splats[std::uint32_t(e.ua)];
                    count += s.ba == b ? 1 : 0;
                    target.draw(s, y0, y1);
                }
            }
            sc.band_drawn[band] = count;
        }
    });
    for (const int c : sc.band_drawn) drawn += c;
    m_drawn = drawn;
}

}  // namespace deepsea
