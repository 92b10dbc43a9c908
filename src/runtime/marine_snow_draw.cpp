// MarineSnow::draw: the particles of a frame lit in float rows (snow_light.h), tested against
// the surface and drawn into the image by bands of rows in parallel, each band taking its
// particles in id order, so that the image and the ids are the same at any thread count.

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "deepsea/runtime/marine_snow.h"
#include "deepsea/runtime/snow_light.h"

namespace deepsea {

namespace {

/// Particles a task lights and sets up at a time.
constexpr std::size_t kBlock = 1024;
/// Rows per band of the drawing pass.
constexpr int kBandRows = 16;

/// A particle as drawn: pixel centre, disc radius (0.5: a bilinear splat into four pixels),
/// planar depth, the light it brings (radiance times its image's area in pixels, per channel)
/// and the disc's coverage normaliser.
struct Splat {
    float u, v, radius, z;
    float energy[3];
    float inv_cover;
    int va, vb;        ///< rows touched
    int iu, iv;        ///< the centre's pixel
    std::uint32_t id;  ///< 0: not drawn
};

bool open_water(float z) { return !(z > 0.0f) || !std::isfinite(z); }

/// Coverage of pixel (x, y) by a disc of radius R centred at (u, v): linear over the last
/// pixel.
inline float coverage(float u, float v, float R, int x, int y) {
    const float dx = float(x) - u, dy = float(y) - v;
    return std::clamp(R + 0.5f - std::sqrt(dx * dx + dy * dy), 0.0f, 1.0f);
}

/// Where a disc is drawn: every pixel it touches, also off the image (so that an edge
/// particle loses what falls outside).
struct Window {
    int ua, ub, va, vb;
};

inline Window window(const Splat& s) {
    if (s.radius <= 0.5f) {
        const int x0 = int(std::floor(s.u)), y0 = int(std::floor(s.v));
        return {x0, x0 + 1, y0, y0 + 1};
    }
    const float R = s.radius;
    return {int(std::floor(s.u - R - 0.5f)), int(std::ceil(s.u + R + 0.5f)),
            int(std::floor(s.v - R - 0.5f)), int(std::ceil(s.v + R + 0.5f))};
}

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

    /// Draws the rows y0..y1 of splat s.
    void draw(const Splat& s, int y0, int y1) const {
        const Window w = window(s);
        y0 = std::max(y0, std::max(w.va, 0));
        y1 = std::min(y1, std::min(w.vb, H - 1));
        const int x0 = std::max(w.ua, 0), x1 = std::min(w.ub, W - 1);
        if (s.radius <= 0.5f) {
            // A particle smaller than a pixel: its light shared bilinearly by four pixels.
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

}  // namespace

void MarineSnow::draw(const Camera& cam, const Image& zdepth, Image& final, Image* snow,
                      Image* ids) const {
    const std::vector<SnowParticle> particles = snow_particles(m_settings, cam, m_key, m_pose);
    const ThinLens lens{cam.fx, m_settings.pixel_pitch_um, m_settings.f_number,
                        m_settings.focus_distance_m};
    const int W = cam.width, H = cam.height;
    const std::size_t n = particles.size();
    if (ids) m_best.assign(std::size_t(W) * H, 0.0f);
    std::vector<Splat> splats(n);
    // Rows: x, y, z, 1/|X|, D, the three energies and five of scratch.
    m_rows.resize(13 * n);
    float* rows = m_rows.data();
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, kBlock), [&](const auto& range) {
        const std::size_t b = range.begin(), m = range.end() - b;
        float* x = rows + b;
        float* y = x + n;
        float* z = y + n;
        float* inv_d2 = z + n;
        float* D = inv_d2 + n;
        float* er = D + n;
        float* eg = er + n;
        float* eb = eg + n;
        const SnowLightScratch scratch{eb + n, eb + 2 * n, eb + 3 * n, eb + 4 * n, eb + 5 * n};
        for (std::size_t q = 0; q < m; ++q) {
            const SnowParticle& pt = particles[b + q];
            x[q] = float(pt.position.x);
            y[q] = float(pt.position.y);
            z[q] = float(pt.position.z);
            inv_d2[q] = float(1.0 / length(pt.position));
            D[q] = float(pt.diameter);
        }
        snow_light(m_rig, m_water, m_settings.snow, cam.fx, cam.fy,
                   ParticleRows{int(m), x, y, z, inv_d2, D}, er, eg, eb, scratch, m_scattered);
        for (std::size_t q = 0; q < m; ++q) {
            const SnowParticle& pt = particles[b + q];
            const Vec3& X = pt.position;
            Splat& s = splats[b + q];
            s.id = 0;  // not drawn
            const double u = cam.fx * X.x / X.z + cam.cx, v = cam.fy * X.y / X.z + cam.cy;
            s.iu = std::clamp(int(std::lround(u)), 0, W - 1);
            s.iv = std::clamp(int(std::lround(v)), 0, H - 1);
            s.u = float(u);
            s.v = float(v);
            s.radius = float(snow_disc_radius_px(cam, lens, X, pt.diameter));
            s.z = float(X.z);
            s.energy[0] = er[q];
            s.energy[1] = eg[q];
            s.energy[2] = eb[q];
            const Window w = window(s);
            s.va = w.va;
            s.vb = w.vb;
            s.inv_cover = 1.0f;
            if (s.radius > 0.5f) {
                // Normalised over the disc: the particle's light is spread, not multiplied.
                float total = 0.0f;
                for (int yy = w.va; yy <= w.vb; ++yy)
                    for (int xx = w.ua; xx <= w.ub; ++xx)
                        total += coverage(s.u, s.v, s.radius, xx, yy);
                if (!(total > 0.0f)) continue;
                s.inv_cover = 1.0f / total;
            }
            s.id = pt.id;
        }
    });

    // A particle whose centre lies behind the surface at its pixel is not drawn: tested by
    // bands of the centre's row, each band's depth read in order first where it is dense.
    const int bands = (H + kBandRows - 1) / kBandRows;
    const Target target{zdepth, final, snow, ids, m_best.data(), W, H};
    std::vector<float> sinks(std::size_t(bands), 0.0f);
    {
        std::vector<std::uint32_t> start(std::size_t(bands) + 1, 0);
        for (const Splat& s : splats)
            if (s.id != 0) ++start[std::size_t(s.iv / kBandRows) + 1];
        for (int b = 0; b < bands; ++b) start[std::size_t(b) + 1] += start[std::size_t(b)];
        std::vector<std::uint32_t> order(start.back()), fill(start.begin(), start.end() - 1);
        for (std::size_t q = 0; q < n; ++q)
            if (splats[q].id != 0)
                order[fill[std::size_t(splats[q].iv / kBandRows)]++] = std::uint32_t(q);
        tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const auto& range) {
            for (int b = range.begin(); b != range.end(); ++b) {
                const int y0 = b * kBandRows, y1 = std::min(H, y0 + kBandRows) - 1;
                const std::uint32_t i0 = start[std::size_t(b)], i1 = start[std::size_t(b) + 1];
                if (std::int64_t(i1 - i0) * 128 > std::int64_t(y1 - y0 + 1) * W)
                    sinks[std::size_t(b)] = target.warm(y0, y1, false);
                for (std::uint32_t i = i0; i < i1; ++i) {
                    Splat& s = splats[order[i]];
                    const float zs = zdepth.row(s.iv)[s.iu];
                    if (!open_water(zs) && zs <= s.z) s.id = 0;  // behind the surface
                }
            }
        });
    }

    // Each band's particles, in id order (a counting sort by band).
    std::vector<std::uint32_t> start(std::size_t(bands) + 1, 0);
    int drawn = 0;
    const auto band_span = [&](const Splat& s) {
        return std::pair{std::max(s.va, 0) / kBandRows, std::min(s.vb, H - 1) / kBandRows};
    };
    for (const Splat& s : splats) {
        if (s.id == 0) continue;
        ++drawn;
        if (s.vb < 0 || s.va > H - 1) continue;
        const auto [b0, b1] = band_span(s);
        for (int b = b0; b <= b1; ++b) ++start[std::size_t(b) + 1];
    }
    for (int b = 0; b < bands; ++b) start[std::size_t(b) + 1] += start[std::size_t(b)];
    std::vector<std::uint32_t> order(start.back()), fill(start.begin(), start.end() - 1);
    for (std::size_t q = 0; q < n; ++q) {
        const Splat& s = splats[q];
        if (s.id == 0 || s.vb < 0 || s.va > H - 1) continue;
        const auto [b0, b1] = band_span(s);
        for (int b = b0; b <= b1; ++b) order[fill[std::size_t(b)]++] = std::uint32_t(q);
    }

    tbb::parallel_for(tbb::blocked_range<int>(0, bands, 1), [&](const auto& range) {
        for (int b = range.begin(); b != range.end(); ++b) {
            const int y0 = b * kBandRows, y1 = std::min(H, y0 + kBandRows) - 1;
            const std::uint32_t i0 = start[std::size_t(b)], i1 = start[std::size_t(b) + 1];
            // Warm when the particles would touch most of the band's cache lines anyway.
            if (std::int64_t(i1 - i0) * 64 > std::int64_t(y1 - y0 + 1) * W)
                sinks[std::size_t(b)] = target.warm(y0, y1, true);
            for (std::uint32_t i = i0; i < i1; ++i) {
                target.draw(splats[order[i]], y0, y1);
            }
        }
    });
    m_drawn = drawn;
}

}  // namespace deepsea
