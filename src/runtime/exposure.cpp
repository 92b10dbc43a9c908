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

/// One counting pass over the image's pixels, both threads: with top null, by the keys' top
/// 16 bits; else by the low 16 bits of the keys whose top bits are top[k].
KeyCounts count_keys(const Image& img, const std::uint32_t* top) {
    const std::size_t ch = std::size_t(img.channels), n = img.data.size() / ch;
    tbb::enumerable_thread_specific<KeyCounts> counts;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const auto& r) {
        KeyCounts& c = counts.local();
        for (std::size_t i = r.begin(); i < r.end(); ++i) {
            const float* p = &img.data[i * ch];
            // Rec. 709 luminance; a pixel whose luminance is not finite counts nowhere
            const float q[4] = {0.2126f * p[0] + 0.7152f * p[1] + 0.0722f * p[2], p[0], p[1], p[2]};
            if (!std::isfinite(q[0])) continue;
            ++c.pixels;
            for (int k = 0; k < 4; ++k) {
                const std::uint32_t key = order_key(q[k]);
                if (!top) {
                    ++c.bins[k * 65536 + (key >> 16)];
                } else if ((key >> 16) == top[k]) {
                    ++c.bins[k * 65536 + (key & 0xffffu)];
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
