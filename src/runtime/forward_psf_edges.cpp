// How the scene dims beyond the frame's edges, for the forward scatter from transport
// (forward_psf_blur.h: EdgeFalloff, edge_falloff, and the blur's fading borders per grid;
// docs/model.md, "Forward scatter from transport").

#include <algorithm>
#include <cmath>
#include <vector>

#include "deepsea/optics/normals.h"
#include "deepsea/runtime/forward_psf_blur.h"

namespace deepsea {

namespace {

constexpr int kSamples = 12;    ///< distances beyond each edge
constexpr double kReach = 3.5;  ///< farthest distance, in the frame's larger side

}  // namespace

float EdgeFalloff::at(const std::vector<float>& side, int border, int c, float s) const {
    const int K = samples();
    if (K == 0 || s <= 0.0f) return 1.0f;
    const int n = &side == &left || &side == &right ? height : width;
    const float* f = side.data() + (std::size_t(c) * n + border) * K;
    const int k = int(std::upper_bound(dist.begin(), dist.end(), s) - dist.begin());
    if (k >= K) return f[K - 1];
    const float d0 = k == 0 ? 0.0f : dist[k - 1], f0 = k == 0 ? 1.0f : f[k - 1];
    return f0 + (s - d0) / (dist[k] - d0) * (f[k] - f0);
}

void ForwardPsfBlur::fade_grid(const EdgeFalloff& beyond, int f, int w, int h, int r) {
    // A grid cell k beyond the edge lies k f pixels beyond the border cell, whose block mean
    // stands for its middle pixel; a grid row or column samples the border at its middle.
    // EdgeFalloff::at, with each distance's two samples and weight found once.
    const int W = m_width, H = m_height, K = beyond.samples();
    for (auto& v : m_fade) v.resize(std::size_t(3) * std::max(w, h) * r);
    const auto side = [&](const std::vector<float>& src, int n, int border, int c) {
        return src.data() + (std::size_t(c) * n + border) * K;
    };
    for (int k = 1; k <= r; ++k) {
        const float s = float(k * f);
        const int i =
            int(std::upper_bound(beyond.dist.begin(), beyond.dist.end(), s) - beyond.dist.begin());
        // factor = (1 - t) at(i - 1) + t at(i), at(-1) = 1; beyond the last sample, the last
        const int i0 = std::min(i, K) - 1, i1 = std::min(i, K - 1);
        const float d0 = i == 0 ? 0.0f : beyond.dist[i0];
        const float t = i >= K ? 1.0f : (s - d0) / (beyond.dist[i1] - d0);
        const auto at = [&](const float* src) {
            const float a = i0 < 0 ? 1.0f : src[i0];
            return a + t * (src[i1] - a);
        };
        for (int c = 0; c < 3; ++c) {
            for (int y = 0; y < h; ++y) {
                const int v = std::min(y * f + f / 2, H - 1);
                const std::size_t o = (std::size_t(c) * h + y) * r + k - 1;
                m_fade[0][o] = at(side(beyond.left, H, v, c));
                m_fade[1][o] = at(side(beyond.right, H, v, c));
            }
            for (int x = 0; x < w; ++x) {
                const int u = std::min(x * f + f / 2, W - 1);
                const std::size_t o = (std::size_t(c) * r + k - 1) * w + x;
                m_fade[2][o] = at(side(beyond.top, W, u, c));
                m_fade[3][o] = at(side(beyond.bottom, W, u, c));
            }
        }
    }
}

void edge_falloff(const Camera& cam, const Image& zdepth, const IrradianceSource& lamps,
                  const ForwardPsf& psf, EdgeFalloff& out) {
    const int W = cam.width, H = cam.height, K = kSamples;
    out.width = W;
    out.height = H;
    out.dist.resize(K);
    const double reach = kReach * std::max(W, H);
    for (int k = 0; k < K; ++k) out.dist[k] = float(reach * std::pow(double(k + 1) / K, 2.0));
    // side 0..3: left, right (along rows), top, bottom (along columns)
    std::vector<float>* sides[4] = {&out.left, &out.right, &out.top, &out.bottom};
    const int count[4] = {H, H, W, W};
    // Sampled border pixels of every side, then their points: the border pixel and K beyond.
    struct Sample {
        int side, i;
    };
    thread_local std::vector<Sample> samples;
    thread_local std::vector<float> px, py, pz, nx, ny, nz, E, T;
    samples.clear();
    for (int s = 0; s < 4; ++s) {
        for (int i = 0;; i = std::min(i + edge_falloff_step(count[s]), count[s] - 1)) {
            samples.push_back({s, i});
            if (i == count[s] - 1) break;
        }
    }
    const std::size_t n = samples.size() * (K + 1);
    for (auto* v : {&px, &py, &pz, &nx, &ny, &nz, &T}) v->assign(n, 0.0f);
    E.assign(3 * n, 0.0f);
    for (std::size_t m = 0; m < samples.size(); ++m) {
        const int s = samples[m].side, i = samples[m].i;
        const int u = s == 0 ? 0 : s == 1 ? W - 1 : i, v = s == 2 ? 0 : s == 3 ? H - 1 : i;
        const float z = zdepth.at(u, v, 0);
        if (!has_surface(z)) continue;  // open water sends nothing: any factor does
        const Vec3 nb = surface_normal(cam, zdepth, u, v);
        for (int k = 0; k <= K; ++k) {
            const double d = k == 0 ? 0.0 : out.dist[k - 1];
            const double uu = u + (s == 0 ? -d : s == 1 ? d : 0.0);
            const double vv = v + (s == 2 ? -d : s == 3 ? d : 0.0);
            const std::size_t j = m * (K + 1) + k;
            px[j] = float(z * cam.ray_x(uu));
            py[j] = float(z * cam.ray_y(vv));
            pz[j] = z;
            nx[j] = float(nb.x);
            ny[j] = float(nb.y);
            nz[j] = float(nb.z);
            T[j] = float(std::hypot(double(px[j]), double(py[j]), double(z)));
        }
    }
    // One point at a time, as a row of one of no row of the frame (v = -1): unshadowed, and
    // computed where it is (a longer row would interpolate a lamp field's light between its
    // points, which here are no row of a surface).
    for (std::size_t j = 0; j < n; ++j) {
        if (!(pz[j] > 0.0f)) continue;
        const RowGeometry g{-1, 1, &px[j], &py[j], &pz[j], &nx[j], &ny[j], &nz[j]};
        float e[3];
        lamps.irradiance_row(g, e);
        for (int c = 0; c < 3; ++c) E[std::size_t(c) * n + j] = e[c];
    }
    for (int s = 0; s < 4; ++s) sides[s]->assign(std::size_t(3) * count[s] * K, 1.0f);
    for (std::size_t m = 0; m < samples.size(); ++m) {
        const int s = samples[m].side, i = samples[m].i;
        const std::size_t j0 = m * (K + 1);
        if (!(pz[j0] > 0.0f)) continue;
        const Rgb tb = psf.total(T[j0]);
        for (int k = 1; k <= K; ++k) {
            const Rgb tq = psf.total(T[j0 + k]);
            for (int c = 0; c < 3; ++c) {
                const float eb = E[std::size_t(c) * n + j0], eq = E[std::size_t(c) * n + j0 + k];
                const double f =
                    (eb > 0.0f ? double(eq) / eb : 1.0) * (tb[c] > 0.0 ? tq[c] / tb[c] : 1.0);
                (*sides[s])[(std::size_t(c) * count[s] + i) * K + k - 1] =
                    std::isfinite(f) ? float(f) : 1.0f;
            }
        }
    }
    // border pixels between two samples: linear between theirs
    for (std::size_t m = 0; m + 1 < samples.size(); ++m) {
        const Sample a = samples[m], b = samples[m + 1];
        if (a.side != b.side || b.i - a.i < 2) continue;
        std::vector<float>& f = *sides[a.side];
        const int N = count[a.side];
        for (int c = 0; c < 3; ++c) {
            for (int i = a.i + 1; i < b.i; ++i) {
                const float t = float(i - a.i) / float(b.i - a.i);
                for (int k = 0; k < K; ++k) {
                    const float fa = f[(std::size_t(c) * N + a.i) * K + k];
                    const float fb = f[(std::size_t(c) * N + b.i) * K + k];
                    f[(std::size_t(c) * N + i) * K + k] = fa + t * (fb - fa);
                }
            }
        }
    }
}

}  // namespace deepsea
