#include "deepsea/camera/bayer.h"

#include <array>

namespace deepsea {

namespace {

constexpr std::array<const char*, 5> kNames = {"none", "rggb", "bggr", "grbg", "gbrg"};

}  // namespace

const char* bayer_name(BayerPattern p) { return kNames[std::size_t(p)]; }

std::optional<BayerPattern> bayer_from_name(const std::string& name) {
    for (std::size_t i = 0; i < kNames.size(); ++i)
        if (name == kNames[i]) return BayerPattern(i);
    return std::nullopt;
}

std::string bayer_names() {
    std::string s;
    for (const char* n : kNames) s += (s.empty() ? "" : ", ") + std::string(n);
    return s;
}

void demosaic_row(const Image& mosaic, BayerPattern p, int v, float* dst_rgb) {
    // Weights of the 3 x 3 neighbourhood by |du| + |dv| (0: 4, 1: 2, 2: 1); G ignores the
    // diagonals (its nearest photosites are the edge neighbours, and at a G site the diagonal
    // G are farther than the site itself).
    const int w = mosaic.width, h = mosaic.height;
    for (int u = 0; u < w; ++u) {
        float sum[3] = {0.0f, 0.0f, 0.0f}, weight[3] = {0.0f, 0.0f, 0.0f};
        for (int dv = -1; dv <= 1; ++dv) {
            const int y = v + dv;
            if (y < 0 || y >= h) continue;
            const float* row = mosaic.row(y);
            for (int du = -1; du <= 1; ++du) {
                const int x = u + du;
                if (x < 0 || x >= w) continue;
                const int c = bayer_channel(p, x, y), d = (du != 0) + (dv != 0);
                if (c == 1 && d == 2) continue;
                const float k = float(4 >> d);
                sum[c] += k * row[3 * x + c];
                weight[c] += k;
            }
        }
        // Every 3 x 3 neighbourhood (even a corner's 2 x 2) holds each channel at least once.
        for (int c = 0; c < 3; ++c) dst_rgb[3 * u + c] = sum[c] / weight[c];
    }
}

void demosaic(const Image& mosaic, BayerPattern p, Image& dst, const Parallel& par) {
    if (dst.width != mosaic.width || dst.height != mosaic.height || dst.channels != 3)
        dst = Image(mosaic.width, mosaic.height, 3);
    parallel_for(
        std::size_t(mosaic.height),
        [&](std::size_t v0, std::size_t v1) {
            for (int v = int(v0); v < int(v1); ++v) demosaic_row(mosaic, p, v, dst.row(v));
        },
        par.or_grain(16));
}

}  // namespace deepsea
