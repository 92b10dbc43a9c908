#pragma once
// The equidistant image's radial map (ForwardPsfBlur::set_camera), in arithmetic that vectorises.

#include <algorithm>
#include <cmath>

namespace deepsea::equidistant {

/// atan(r) / r for q = r^2 >= 0: an equidistant image's radius over the pinhole's. A minimax
/// polynomial of atan on [0, 1] (within 1e-5 rad), atan(r) = pi/2 - atan(1/r) beyond; no
/// branches and no division at r = 0.
inline float atan_ratio(float q) {
    const bool far = q > 1.0f;
    const float x2 = far ? 1.0f / q : q;  // the argument in [0, 1], squared
    const float p =
        0.99997726f +
        x2 * (-0.33262347f +
              x2 * (0.19354346f + x2 * (-0.11643287f + x2 * (0.05265332f + x2 * -0.01172120f))));
    // near: atan(r) / r = p; far: (pi/2 - p / r) / r, with 1 / r = sqrt(x2)
    const float inv_r = std::sqrt(x2);
    return far ? (1.5707963f - p * inv_r) * inv_r : p;
}

/// The kernel's covariance over sigma^2 in pinhole pixels at normalised image position (a, b)
/// (a = (u - cx) / fx, b likewise) for a Gaussian of the equidistant image: J J^T, J the
/// pinhole's pixels over the equidistant image's, 1 + r^2 radially and r / atan(r) across.
inline void stretch(float a, float b, float& xx, float& xy, float& yy) {
    const float q = a * a + b * b;
    const float s = atan_ratio(q);
    const float t2 = 1.0f / (s * s), radial = 1.0f + q;
    // (radial^2 - t2) / q, 4/3 as q -> 0
    const float d = q > 1e-6f ? (radial * radial - t2) / std::max(q, 1e-6f) : 4.0f / 3.0f;
    xx = t2 + d * a * a;
    xy = d * a * b;
    yy = t2 + d * b * b;
}

}  // namespace deepsea::equidistant
