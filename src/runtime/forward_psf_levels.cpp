// The forward scatter's cascade of grids (forward_psf_blur.h): which downsampling factor each
// scale's blur runs at, and the variance that downsampling and upsampling back add. Compiled as
// forward_psf_blur.cpp is (the factors it picks, and so the blur's bits, follow from these).

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "deepsea/runtime/forward_psf_blur.h"

namespace deepsea {

namespace {

/// The variance resampling_variance gives, measured on an impulse at every place of a block.
double measured_resampling_variance(int factor) {
    // One row of 16 blocks; an impulse at each place p of block 8 is box-averaged into its
    // block, upsampled by two until full resolution, and the spread about p measured.
    const int n = 16 * factor;
    double sum = 0.0;
    for (int p = 0; p < factor; ++p) {
        const int x = 8 * factor + p;
        std::vector<double> g(16, 0.0);
        g[x / factor] = 1.0 / factor;
        while (int(g.size()) < n) {
            const int lo = int(g.size());
            std::vector<double> fine(2 * g.size());
            for (int i = 0; i < 2 * lo; ++i) {
                const double fx = (i + 0.5) / 2.0 - 0.5;
                const int a = std::clamp(int(std::floor(fx)), 0, lo - 1);
                const int b = std::min(a + 1, lo - 1);
                const double t = std::clamp(fx - a, 0.0, 1.0);
                fine[i] = g[a] + t * (g[b] - g[a]);
            }
            g.swap(fine);
        }
        for (int u = 0; u < n; ++u) sum += g[u] * double(u - x) * double(u - x);
    }
    return sum / factor;
}

}  // namespace

int ForwardPsfBlur::level_factor(double sigma, int width, int height) {
    int f = 1;
    while (f < 128 && std::min(width, height) / (2 * f) >= 8 &&
           resampling_variance(2 * f) <= sigma * sigma * (1.0 + 1e-9)) {
        f *= 2;
    }
    return f;
}

double ForwardPsfBlur::resampling_variance(int factor) {
    if (factor <= 1) return 0.0;
    // Factors 2 .. 128, all that level_factor and resize ask for, measured once a process (the
    // measurement takes 1.6 ms at 128, and a frame size's first frame asked for it a dozen
    // times).
    static const std::array<double, 8> known = [] {
        std::array<double, 8> v{};
        for (int k = 1; k < 8; ++k) v[k] = measured_resampling_variance(1 << k);
        return v;
    }();
    for (int k = 1; k < 8; ++k)
        if (factor == 1 << k) return known[k];
    return measured_resampling_variance(factor);
}

}  // namespace deepsea
