#pragma once
/// \file Beer-Lambert transmission (docs/model.md, "Direct signal"), the factor every light
/// path through the water carries: lamp to surface, surface to camera, and the
/// transmission layer. Header-inline and templated on the number type for the reasons in
/// lamp.h.

#include <cmath>

#include "deepsea/core/fast_math.h"
#include "deepsea/core/vec.h"

namespace deepsea {

/// Fraction exp(-c d) of the light that crosses d metres of water of beam attenuation c (1/m)
/// without being absorbed or scattered. Math: whose exp (core/fast_math.h; the runtime's rows
/// take FastMath's).
template <class Math = ExactMath, class T>
inline T transmission(T c, T d) {
    return Math::exp(-c * d);
}

/// transmission per channel (R, G, B) over d metres.
inline Rgb transmission(const Rgb& c, double d) {
    return {transmission(c.r, d), transmission(c.g, d), transmission(c.b, d)};
}

}  // namespace deepsea
