#pragma once
/// \file A lamp's scattered-light coefficients at rows of points (lamps.cpp: the surfaces'
/// grid; snow_light.cpp: marine snow's particles). Inline so that it vectorises inside each
/// caller's `omp simd` loop and target clone; both callers are compiled with the hot loops'
/// flags (CMakeLists.txt).

#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"

namespace deepsea {

/// Lamp L's scattered-light coefficients per unit on-axis intensity (optics'
/// lamp_field_quadratic, in the camera frame) at n camera-frame points (x, y, z):
/// out[(c * kQuadraticCount + i) * n + k] for channel c, coefficient i, point k.
[[gnu::always_inline]] inline void lamp_field_rows(const Light& L, const LampField& field, int n,
                                                   const float* __restrict x,
                                                   const float* __restrict y,
                                                   const float* __restrict z,
                                                   float* __restrict out) {
    Vec3 ex, ey;
    lamp_frame(L.direction, ex, ey);
    const LampFieldView<float> f(field);
    const float ox = float(L.position.x), oy = float(L.position.y), oz = float(L.position.z);
    const float exx = float(ex.x), exy = float(ex.y), exz = float(ex.z);
    const float eyx = float(ey.x), eyy = float(ey.y), eyz = float(ey.z);
    const float ax = float(L.direction.x), ay = float(L.direction.y), az = float(L.direction.z);
#pragma omp simd
    for (int k = 0; k < n; ++k) {
        // into the lamp frame: the equation is optics' (lamp_field.h)
        const float qx = x[k] - ox, qy = y[k] - oy, qz = z[k] - oz;
        lamp_field_quadratic(f, exx, exy, exz, eyx, eyy, eyz, ax, ay, az,
                             exx * qx + exy * qy + exz * qz, eyx * qx + eyy * qy + eyz * qz,
                             ax * qx + ay * qy + az * qz, out + k, n);
    }
}

}  // namespace deepsea
