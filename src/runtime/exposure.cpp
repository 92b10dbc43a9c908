#include "deepsea/runtime/exposure.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "clones.h"
#include "deepsea/core/error.h"

namespace deepsea {

Exposure parse_exposure(const std::string& text) {
    Exposure e;
    if (text == "auto") return e;
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || !(v > 0.0) || !std::isfinite(v)) {
        throw ConfigError("exposure: expected 'auto' or a positive number, got '" + text + "'");
    }
    e.automatic = false;
    e.factor = v;
    return e;
}

namespace {

/// A float's bits as an unsigned key that sorts as the float does (negatives with every bit
/// flipped, the rest with the sign bit set), and back.
std::uint32_t order_key(float x) {
    std::uint32_t b;
    std::memcpy(&b, &x, sizeof b);
    return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
float from_order_key(std::uint32_t k) {
    const std::uint32_t b = (k & 0x80000000u) ? (k & 0x7fffffffu) : ~k;
    float x;
    std::memcpy(&x, &b, sizeof x);
    return x;
}

/// Counts of the four quantities' keys (luminance, R, G, B) by their top 16 bits (first pass)
/// or, among those whose top bits were chosen, by their low 16 bits (second pass).
struct KeyCounts {
    std::vector<std::uint32_t> bins = std::vector<std::uint32_t>(4 * 65536, 0);
    std::size_t pixels = 0;
};

/// The four quantities' keys of `n` RGB pixels (3 floats each): luminance (Rec. 709), R, G, B,
/// and whether the luminance is finite. A vector loop in the AVX2 clone, without FMA: the
/// luminance rounds as the scalar sum's does.
DEEPSEA_CLONES_NO_FMA
void rgb_keys(const float* __restrict p, int n, std::uint32_t* __restrict y,
              std::uint32_t* __restrict r, std::uint32_t* __restrict g, std::uint32_t* __restrict b,
              unsigned char* __restrict finite) {
    for (int i = 0; i < n; ++i) {
        const float q = 0.2126f * p[3 * i] + 0.7152f * p[3 * i + 1] + 0.0722f * p[3 * i + 2];
        std::uint32_t bits;
        std::memcpy(&bits, &q, sizeof bits);
        finite[i] = (bits & 0x7f800000u) != 0x7f800000u;
        y[i] = order_key(q);
        r[i] = order_key(p[3 * i]);
        g[i] = order_key(p[3 * i + 1]);
        b[i] = order_key(p[3 * i + 2]);
    }
}

/// One counting pass over the image's pixels, both threads: with top null, by the keys' top
/// 16 bits; else by the low 16 bits of the keys whose top bits are top[k]. The keys are made
/// a block of pixels at a time (rgb_keys), then counted.
KeyCounts count_keys(const Image& img, const std::uint32_t* top) {
    const std::size_t ch = std::size_t(img.channels), n = img.data.size() / ch;
    constexpr int kBlock = 512;
    struct Keys {
        std::uint32_t key[4][kBlock];
        unsigned char finite[kBlock];
    };
    tbb::enumerable_thread_specific<KeyCounts> counts;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
        KeyCounts& c = counts.local();
        Keys keys;
        std::vector<float> rgb;  // other than 3 channels: the pixels' first three
        for (std::size_t i0 = r.begin(); i0 < r.end(); i0 += kBlock) {
            const int m = int(std::min<std::size_t>(kBlock, r.end() - i0));
            const float* p = &img.data[i0 * ch];
            if (ch != 3) {
                rgb.resize(3 * std::size_t(m));
                for (int i = 0; i < m; ++i) std::copy_n(p + i * ch, 3, &rgb[3 * std::size_t(i)]);
                p = rgb.data();
            }
            rgb_keys(p, m, keys.key[0], keys.key[1], keys.key[2], keys.key[3], keys.finite);
            // a pixel whose luminance is not finite counts nowhere
            for (int i = 0; i < m; ++i) {
                if (!keys.finite[i]) continue;
                ++c.pixels;
                for (int k = 0; k < 4; ++k) {
                    const std::uint32_t key = keys.key[k][i];
                    if (!top) {
                        ++c.bins[k * 65536 + (key >> 16)];
                    } else if ((key >> 16) == top[k]) {
                        ++c.bins[k * 65536 + (key & 0xffffu)];
                    }
                }
            }
        }
    });
    KeyCounts sum;
    for (const KeyCounts& c : counts) {
        sum.pixels += c.pixels;
        for (std::size_t b = 0; b < sum.bins.size(); ++b) sum.bins[b] += c.bins[b];
    }
    return sum;
}

/// The bin of quantity k that holds the value of rank `left` (0-based) in the counts, and
/// that value's rank among the bin's own.
std::uint32_t bin_of(const KeyCounts& c, int k, std::size_t& left) {
    std::uint32_t b = 0;
    while (left >= c.bins[k * 65536 + b]) left -= c.bins[k * 65536 + b++];
    return b;
}

/// The rank (0-based, ascending) of the value that at most `fraction` of `count` values
/// exceed.
std::size_t upper_rank(std::size_t count, double fraction) {
    const std::size_t over = std::size_t(fraction * double(count));
    return count - 1 - std::min(over, count - 1);
}

}  // namespace

double exposure_factor(const Exposure& e, const Image& radiance) {
    if (!e.automatic) return e.factor;
    if (radiance.channels < 3) throw InputError("exposure: the image needs 3 channels");
    // The luminance percentile (ignoring a few specular or near-lamp outliers) and each
    // channel's clipping quantile, selected exactly by two counting passes over the values'
    // sort keys, the top 16 bits and then the low 16: no copy of the values (8 MB at 1080p)
    // and no sort.
    const KeyCounts first = count_keys(radiance, nullptr);
    if (first.pixels == 0) return 1.0;
    const std::size_t r_rgb = upper_rank(first.pixels, e.max_clipped);
    std::size_t left[4] = {upper_rank(first.pixels, 1.0 - e.percentile), r_rgb, r_rgb, r_rgb};
    std::uint32_t top[4];
    for (int k = 0; k < 4; ++k) top[k] = bin_of(first, k, left[k]);
    const KeyCounts second = count_keys(radiance, top);
    float value[4];
    for (int k = 0; k < 4; ++k)
        value[k] = from_order_key(top[k] << 16 | bin_of(second, k, left[k]));
    const double p = value[0];
    if (!(p > 0.0)) return 1.0;
    double factor = e.target / p;
    for (int c = 1; c < 4; ++c) {
        const double q = value[c];
        if (q > 0.0) factor = std::min(factor, 1.0 / q);
    }
    return factor;
}

Image apply_exposure(const Image& radiance, double factor) {
    Image out = radiance;
    for (float& v : out.data) v = float(v * factor);
    return out;
}

}  // namespace deepsea
