#include "deepsea/camera/model.h"

#include <charconv>
#include <cmath>

#include "deepsea/camera/auto_exposure.h"
#include "deepsea/camera/processing.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

/// Shortest text that reads back to exactly v.
std::string fmt(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

const char* const kChannel[] = {"R", "G", "B"};

/// SchemaError "key: must be <what>, got v" unless ok (false for NaN by construction).
void require(bool ok, const std::string& key, const std::string& what, double v) {
    if (!ok) throw SchemaError(key, "must be " + what + ", got " + fmt(v));
}

void require_finite(const std::string& key, double v) {
    require(std::isfinite(v), key, "a finite number", v);
}

/// The lower bound (`low`: "> 0", ">= 1", ...) and an upper one that catches unit mistakes
/// and overflow, each with its own message.
void bounded(bool low_ok, const std::string& low, double high, const std::string& unit,
             const std::string& key, double v) {
    require(low_ok, key, low, v);
    require(v <= high, key, "at most " + fmt(high) + unit, v);
}

void validate_lens(const Lens& l) {
    bounded(l.f_number > 0.0, "> 0", 1e3, "", "camera.lens.f_number", l.f_number);
    require(l.transmittance > 0.0 && l.transmittance <= 1.0, "camera.lens.transmittance",
            "in (0, 1]", l.transmittance);
    bounded(l.focus_distance_m > 0.0, "> 0", 1e4, " metres", "camera.lens.focus_distance_m",
            l.focus_distance_m);
    const Vignetting& v = l.vignetting;
    require_finite("camera.lens.vignetting.k1", v.k1);
    require_finite("camera.lens.vignetting.k2", v.k2);
    require_finite("camera.lens.vignetting.k3", v.k3);
    const Distortion& d = l.distortion;
    require_finite("camera.lens.distortion.k1", d.k1);
    require_finite("camera.lens.distortion.k2", d.k2);
    require_finite("camera.lens.distortion.p1", d.p1);
    require_finite("camera.lens.distortion.p2", d.p2);
    require_finite("camera.lens.distortion.k3", d.k3);
}

void validate_sensor(const Sensor& s) {
    const std::string k = "camera.sensor.";
    // 0.5 um (the smallest pixels made) to 1 mm: beyond either it is a unit mistake.
    require(s.pixel_pitch_um >= 0.5 && s.pixel_pitch_um <= 1000.0, k + "pixel_pitch_um",
            "in [0.5, 1000] micrometres", s.pixel_pitch_um);
    bounded(s.exposure_time_ms > 0.0, "> 0", 3.6e6, " ms (an hour)", k + "exposure_time_ms",
            s.exposure_time_ms);
    for (int c = 0; c < 3; ++c) {
        const double q = s.quantum_efficiency[c], w = s.wavelength_nm[c];
        if (!(q > 0.0 && q <= 1.0))
            throw SchemaError(k + "quantum_efficiency", std::string("must be in (0, 1] (") +
                                                            kChannel[c] + " is " + fmt(q) + ")");
        if (!(w >= 200.0 && w <= 1200.0))
            throw SchemaError(k + "wavelength_nm", std::string("must be in [200, 1200] nm (") +
                                                       kChannel[c] + " is " + fmt(w) + ")");
    }
    require(s.bits >= 8 && s.bits <= 16, k + "bits", "an integer from 8 to 16", s.bits);
    bounded(s.full_well >= 1.0, ">= 1", 1e9, " electrons", k + "full_well", s.full_well);
    const double top = std::ldexp(1.0, s.bits) - 1.0;
    if (s.black_level)
        require(*s.black_level >= 0.0 && *s.black_level < top, k + "black_level",
                ">= 0 and below 2^bits - 1 = " + fmt(top) + " DN", *s.black_level);
    if (s.system_gain)
        bounded(*s.system_gain > 0.0, "> 0", 1e6, " DN per electron", k + "system_gain",
                *s.system_gain);
    else
        bounded(s.iso > 0.0, "> 0", 1e7, "", k + "iso", s.iso);
    bounded(s.dark_noise >= 0.0, ">= 0", 1e6, " electrons", k + "dark_noise", s.dark_noise);
    bounded(s.dark_current >= 0.0, ">= 0", 1e9, " electrons per second", k + "dark_current",
            s.dark_current);
    bounded(s.dsnu >= 0.0, ">= 0", 1e6, " electrons", k + "dsnu", s.dsnu);
    // Beyond 18 % the Gaussian's 5.42 sigma tail would reach a negative response.
    bounded(s.prnu_percent >= 0.0, ">= 0", 18.0, " %", k + "prnu_percent", s.prnu_percent);
}

void validate_processing(const Processing& p) {
    const std::string k = "camera.processing.";
    if (p.white_balance == WhiteBalance::Gains)
        for (int c = 0; c < 3; ++c)
            if (!(p.gains[c] > 0.0 && p.gains[c] <= 1e3))
                throw SchemaError(k + "white_balance.gains", std::string("must be in (0, 1000] (") +
                                                                 kChannel[c] + " is " +
                                                                 fmt(p.gains[c]) + ")");
    if (p.matrix)
        for (int i = 0; i < 9; ++i)
            require(std::isfinite((*p.matrix)[i]) && std::fabs((*p.matrix)[i]) <= 1e3,
                    k + "matrix[" + std::to_string(i) + "]", "finite, at most 1000 in magnitude",
                    (*p.matrix)[i]);
    if (p.curve == OutputCurve::Gamma)
        require(p.gamma >= 0.1 && p.gamma <= 10.0, k + "curve.gamma", "in [0.1, 10]", p.gamma);
}

void validate_auto_exposure(const AutoExposure& a, const Sensor& s) {
    const std::string k = "camera.auto_exposure.";
    if (a.metering == Metering::Percentile)
        require(a.percentile > 0.0 && a.percentile <= 100.0, k + "metering.percentile",
                "in (0, 100]", a.percentile);
    require(a.target > 0.0 && a.target < 1.0, k + "target", "in (0, 1)", a.target);
    require(a.damping > 0.0 && a.damping <= 1.0, k + "damping", "in (0, 1]", a.damping);
    bounded(a.min_exposure_time_ms > 0.0, "> 0", 3.6e6, " ms (an hour)", k + "min_exposure_time_ms",
            a.min_exposure_time_ms);
    bounded(a.max_exposure_time_ms >= a.min_exposure_time_ms,
            ">= min_exposure_time_ms = " + fmt(a.min_exposure_time_ms) + " ms", 3.6e6,
            " ms (an hour)", k + "max_exposure_time_ms", a.max_exposure_time_ms);
    if (a.min_system_gain)
        bounded(*a.min_system_gain > 0.0, "> 0", 1e6, " DN per electron", k + "min_system_gain",
                *a.min_system_gain);
    // The default maximum follows the minimum; only a given one can lie below it.
    const ExposureLimits lim = exposure_limits(a, s);
    if (a.max_system_gain)
        bounded(lim.max_system_gain >= lim.min_system_gain,
                ">= min_system_gain = " + fmt(lim.min_system_gain) + " DN per electron", 1e6,
                " DN per electron", k + "max_system_gain", lim.max_system_gain);
}

}  // namespace

double max_dn(const Sensor& s) { return std::ldexp(1.0, s.bits) - 1.0; }

double black_level(const Sensor& s) {
    return s.black_level ? *s.black_level : std::ldexp(1.0, s.bits - 6);
}

double system_gain(const Sensor& s) {
    if (s.system_gain) return *s.system_gain;
    return s.iso / 100.0 * (max_dn(s) - black_level(s)) / s.full_well;
}

double electrons_per_radiance(const Lens& lens, const Sensor& sensor, int channel,
                              double exposure_time_ms) {
    const double pitch = sensor.pixel_pitch_um * 1e-6;
    const double irradiance = sensor_irradiance(1.0, lens.transmittance, lens.f_number);
    const double joules = irradiance * pitch * pitch * exposure_time_ms * 1e-3;
    return sensor.quantum_efficiency[channel] * joules /
           photon_energy(sensor.wavelength_nm[channel]);
}

void validate(const CameraModel& m) {
    validate_lens(m.lens);
    validate_sensor(m.sensor);
    validate_processing(m.processing);
    validate_auto_exposure(m.auto_exposure, m.sensor);
}

Rgb grey_world_gains(const Rgb& means) {
    Rgb g(1.0);
    if (!(means.g > 0.0)) return g;
    for (int c = 0; c < 3; ++c)
        if (means[c] > 0.0) g[c] = means.g / means[c];
    return g;
}

}  // namespace deepsea
