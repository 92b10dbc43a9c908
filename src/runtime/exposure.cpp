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

double exposure_factor(const Exposure& e, const Image& radiance) {
    if (!e.automatic) return e.factor;
    // Rec. 709 luminance; the percentile ignores a few specular or near-lamp outliers.
    std::vector<float> lum;
    lum.reserve(std::size_t(radiance.width) * radiance.height);
    for (std::size_t i = 0; i + 2 < radiance.data.size(); i += radiance.channels) {
        const float y = 0.2126f * radiance.data[i] + 0.7152f * radiance.data[i + 1] +
                        0.0722f * radiance.data[i + 2];
        if (std::isfinite(y)) lum.push_back(y);
    }
    if (lum.empty()) return 1.0;
    const std::size_t n = std::min(lum.size() - 1, std::size_t(e.percentile * (lum.size() - 1)));
    std::nth_element(lum.begin(), lum.begin() + n, lum.end());
    const double p = lum[n];
    return p > 0.0 ? e.target / p : 1.0;
}

Image apply_exposure(const Image& radiance, double factor) {
    Image out = radiance;
    for (float& v : out.data) v = float(v * factor);
    return out;
}

}  // namespace deepsea
