#include "deepsea/runtime/exposure.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
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

/// The value that at most `fraction` of `values` exceed (0 for none).
double upper_quantile(std::vector<float>& values, double fraction) {
    if (values.empty()) return 0.0;
    const std::size_t over = std::size_t(fraction * double(values.size()));
    const std::size_t n = values.size() - 1 - std::min(over, values.size() - 1);
    std::nth_element(values.begin(), values.begin() + n, values.end());
    return values[n];
}

}  // namespace

double exposure_factor(const Exposure& e, const Image& radiance) {
    if (!e.automatic) return e.factor;
    // Rec. 709 luminance; the percentile ignores a few specular or near-lamp outliers. Pixels
    // whose luminance is not finite are left out of every quantile. One buffer serves the four
    // quantiles in turn (at 1080p, 8 MB instead of 33 MB at once).
    const std::size_t n = std::size_t(radiance.width) * radiance.height;
    std::vector<float> values;
    values.reserve(n);
    // k = -1: luminance; 0, 1, 2: that channel.
    const auto gather = [&](int k) {
        values.clear();
        for (std::size_t i = 0; i + 2 < radiance.data.size(); i += radiance.channels) {
            const float r = radiance.data[i], g = radiance.data[i + 1], b = radiance.data[i + 2];
            const float y = 0.2126f * r + 0.7152f * g + 0.0722f * b;
            if (!std::isfinite(y)) continue;
            values.push_back(k < 0 ? y : radiance.data[i + k]);
        }
    };
    gather(-1);
    const double p = upper_quantile(values, 1.0 - e.percentile);
    if (!(p > 0.0)) return 1.0;
    double factor = e.target / p;
    for (int c = 0; c < 3; ++c) {
        gather(c);
        const double q = upper_quantile(values, e.max_clipped);
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
