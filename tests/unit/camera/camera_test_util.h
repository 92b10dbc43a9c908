#pragma once
// Shared by the camera stage's tests: flat fields, a camera, per-channel statistics.

#include <cstdint>
#include <vector>

#include "deepsea/camera/camera_stage.h"

namespace deepsea::camera_test {

/// A 3-channel image of one radiance per channel.
inline Image flat(int w, int h, Rgb radiance) {
    Image img(w, h, 3);
    for (std::size_t i = 0; i < img.data.size(); ++i) img.data[i] = float(radiance[int(i % 3)]);
    return img;
}

/// A pinhole camera with the principal point in the middle.
inline Camera pinhole(int w, int h, double f) { return {w, h, f, f, (w - 1) / 2.0, (h - 1) / 2.0}; }

/// A model with no falloff over the image (flat fields stay flat).
inline CameraModel flat_model() {
    CameraModel m;
    m.lens.vignetting.natural = false;
    return m;
}

/// Mean of channel c.
inline double mean(const Image& img, int c) {
    double s = 0.0;
    for (std::size_t i = c; i < img.data.size(); i += 3) s += img.data[i];
    return s / (img.data.size() / 3);
}

/// EMVA 1288's temporal variance of channel c from two frames of the same field:
/// 1/(2N) sum (yA - yB)^2 - (muA - muB)^2 / 2.
inline double temporal_variance(const Image& a, const Image& b, int c) {
    double s = 0.0;
    for (std::size_t i = c; i < a.data.size(); i += 3) {
        const double d = double(a.data[i]) - b.data[i];
        s += d * d;
    }
    const double n = double(a.data.size() / 3), dm = mean(a, c) - mean(b, c);
    return s / (2.0 * n) - dm * dm / 2.0;
}

}  // namespace deepsea::camera_test
