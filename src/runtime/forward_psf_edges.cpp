// How the scene dims beyond the frame's edges, for the forward scatter from transport
// (forward_psf_blur.h, edge_falloff; docs/model.md, "Forward scatter from transport").

#include <algorithm>
#include <cmath>
#include <vector>

#include "deepsea/optics/normals.h"
#include "deepsea/runtime/forward_psf_blur.h"

namespace deepsea {

namespace {

constexpr int kSamples = 12;    ///< distances beyond each edge
constexpr int kBorderStep = 8;  ///< border pixels between lamp evaluations (linear between)
constexpr double kReach = 3.5;  ///< farthest distance, in the frame's larger side

}  // namespace

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
        for (int i = 0;; i = std::min(i + kBorderStep, count[s] - 1)) {
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
