#pragma once
/// \file The camera's mapping from radiance to pixel values: one exposure factor.

#include <string>

#include "deepsea/core/image.h"

namespace deepsea {

/// How the exposure factor is chosen.
struct Exposure {
    bool automatic = true;
    double factor = 1.0;         ///< used when not automatic
    double percentile = 0.995;   ///< automatic: this luminance percentile ...
    double target = 0.85;        ///< ... is mapped to this value, unless that would clip
    double max_clipped = 0.005;  ///< ... more than this fraction of pixels in any one channel
};

/// Parses "auto" or a positive number (ConfigError otherwise).
Exposure parse_exposure(const std::string& text);

/// The factor for an image: the fixed one, or target / luminance percentile, lowered where
/// needed so that in each of R, G and B at most max_clipped of the pixels exceed 1 once
/// exposed (a blue backscatter-dominated frame is limited by blue, not by luminance). 1 for a
/// black image.
double exposure_factor(const Exposure& exposure, const Image& radiance);

/// radiance * factor, channel by channel (values are clamped later by the writer).
Image apply_exposure(const Image& radiance, double factor);

}  // namespace deepsea
