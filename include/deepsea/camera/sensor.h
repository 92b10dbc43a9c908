#pragma once
/// \file Exposure in camera terms (docs/camera.md, "Exposure"): radiance to sensor irradiance,
/// photons, electrons and DN, and the irradiance falloff over the image (vignetting). Pure
/// functions; the stage's row kernels call the templates in float, the tests in double.

#include "deepsea/camera/model.h"

namespace deepsea {

inline constexpr double kPlanck = 6.62607015e-34;     ///< h, J s (SI, exact)
inline constexpr double kSpeedOfLight = 299792458.0;  ///< c, m/s (SI, exact)

/// Energy of one photon of wavelength lambda (nm): h c / lambda, joules.
inline double photon_energy(double wavelength_nm) {
    return kPlanck * kSpeedOfLight / (wavelength_nm * 1e-9);
}

/// The camera equation on the axis: sensor irradiance E = pi L T / (4 N^2), W/m^2, from scene
/// radiance L (W/(m^2 sr)), lens transmittance T and f-number N. Off the axis it is multiplied
/// by the vignetting factor (cos^4 and the polynomial, below).
template <class F>
F sensor_irradiance(F radiance, double transmittance, double f_number) {
    return radiance * F(3.14159265358979323846 * transmittance / (4.0 * f_number * f_number));
}

/// Mean photo-electrons that one unit of radiance (1 W/(m^2 sr)) on the axis gives a pixel in
/// channel c (0 R, 1 G, 2 B) over an exposure of exposure_time_ms:
/// eta_c * E(1) * A * t / (h c / lambda_c), A = pixel_pitch^2. Electrons per W/(m^2 sr).
double electrons_per_radiance(const Lens& lens, const Sensor& sensor, int channel,
                              double exposure_time_ms);

/// Mean dark-current electrons over an exposure: mu_I * t.
inline double dark_electrons(const Sensor& sensor, double exposure_time_ms) {
    return sensor.dark_current * exposure_time_ms * 1e-3;
}

/// cos^4(theta) for a ray with r^2 = tan^2(theta) = x^2 + y^2 (x, y: the ray's Camera::ray_x,
/// ray_y): cos^2(theta) = 1 / (1 + r^2).
template <class F>
F cos4_from_r2(F r2) {
    const F c2 = F(1) / (F(1) + r2);
    return c2 * c2;
}

/// The measured polynomial 1 + k1 r^2 + k2 r^4 + k3 r^6 at r^2.
template <class F>
F vignetting_polynomial(const Vignetting& v, F r2) {
    return F(1) + r2 * (F(v.k1) + r2 * (F(v.k2) + r2 * F(v.k3)));
}

/// The whole falloff at r^2: cos^4 (if natural) times the polynomial.
template <class F>
F vignetting_factor(const Vignetting& v, F r2) {
    const F poly = vignetting_polynomial(v, r2);
    return v.natural ? cos4_from_r2(r2) * poly : poly;
}

/// The falloff at the recorded pixel (u, v) of a camera: r^2 from the pinhole ray of (u, v).
/// With distortion the recorded pixel's position on the sensor sets the angle (the cos^4 is
/// the sensor's geometry), not the undistorted ray it sees.
inline double vignetting_at(const Vignetting& v, const Camera& camera, double u, double vv) {
    const double x = camera.ray_x(u), y = camera.ray_y(vv);
    return vignetting_factor(v, x * x + y * y);
}

}  // namespace deepsea
