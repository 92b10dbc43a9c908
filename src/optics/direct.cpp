#include "deepsea/optics/direct.h"

#include <cmath>

#include "deepsea/optics/lamp.h"

namespace deepsea {

// The per-pixel arithmetic is lamp.h's, shared with the runtime's float rows (lamps.cpp,
// kernels.cpp); this file only loops over the lamps and channels.

Rgb lamp_irradiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n) {
    Rgb e;
    for (const Light& L : rig.lights) {
        const LampGeometry<double> g =
            lamp_geometry(vec3t(L.position - P), vec3t(n), vec3t(L.direction));
        const double spread = lamp_spread(g.d1, g.cos_n);
        if (spread == 0.0) continue;  // the lamp is behind the surface
        const double theta = lamp_angle(g.cos_theta);
        if (L.rid.kind == Rid::Kind::Gaussian) {
            // The runtime's form (lamp.h): the RID's exponential and the transmission's as one.
            if (theta * (180.0 / M_PI) > L.rid.cutoff_deg) continue;  // as Rid's cutoff
            const double sigma = L.rid.sigma_deg / (180.0 / M_PI);
            for (int ch = 0; ch < 3; ++ch) {
                e[ch] +=
                    gaussian_lamp_term(L.intensity[ch], theta, sigma, spread, water.c[ch], g.d1);
            }
            continue;
        }
        const double rid = L.rid(theta);
        for (int ch = 0; ch < 3; ++ch) {
            e[ch] += lamp_term(L.intensity[ch], rid, spread, water.c[ch], g.d1);
        }
    }
    return e;
}

Rgb direct_radiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n,
                    const Rgb& J) {
    const double d2 = length(P);
    const Rgb E = lamp_irradiance(rig, water, P, n);
    return {direct_signal(J.r, E.r, water.c.r, d2), direct_signal(J.g, E.g, water.c.g, d2),
            direct_signal(J.b, E.b, water.c.b, d2)};
}

Rgb surface_radiance(const Rig& rig, const Water& water, const Vec3& P, const Vec3& n,
                     const Rgb& J) {
    const Rgb E = lamp_irradiance(rig, water, P, n);
    return {lambertian_radiance(J.r, E.r), lambertian_radiance(J.g, E.g),
            lambertian_radiance(J.b, E.b)};
}

}  // namespace deepsea
