#include "deepsea/optics/direct.h"

#include <cmath>

namespace deepsea {

Rgb lamp_irradiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n) {
    Rgb e;
    for (const Light& L : rig.lights) {
        const Vec3 to_light = L.position - P;
        const double d1 = length(to_light);
        const Vec3 w = to_light / d1;
        const double cos_n = dot(n, w);
        if (cos_n <= 0.0) continue;
        // intensity toward P (direction light -> P = -w), spread over d1^2, attenuated on the way
        e += L.intensity_toward(-w) * exp(water.c * -d1) * (cos_n / (d1 * d1));
    }
    return e;
}

Rgb direct_radiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n,
                    const Rgb& J) {
    const double d2 = length(P);
    return J * lamp_irradiance(rig, water, P, n) * exp(water.c * -d2) * (1.0 / M_PI);
}

}  // namespace deepsea
