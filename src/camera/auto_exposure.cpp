#include "deepsea/camera/auto_exposure.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "deepsea/camera/sensor.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace {

/// Frames of damped steps that bring a log error e within tol: (1 - d)^n e <= tol.
int damped_frames(double d, double e, double tol) {
    if (e <= tol) return 0;
    if (d >= 1.0) return 1;
    return int(std::ceil(std::log(tol / e) / std::log(1.0 - d)));
}

/// The target the controller steers to: never at or above where the frame saturates.
double reachable_target(double target, double clip_level) {
    return std::min(target, kSaturatedFraction * clip_level);
}

}  // namespace

ExposureLimits exposure_limits(const AutoExposure& ae, const Sensor& sensor) {
    ExposureLimits l;
    l.min_exposure_time_ms = ae.min_exposure_time_ms;
    l.max_exposure_time_ms = ae.max_exposure_time_ms;
    l.min_system_gain = ae.min_system_gain ? *ae.min_system_gain : system_gain(sensor);
    l.max_system_gain =
        ae.max_system_gain ? *ae.max_system_gain : std::min(16.0 * l.min_system_gain, 1e6);
    return l;
}

ExposureReading meter_exposure(const AutoExposure& ae, const Sensor& sensor,
                               const std::vector<std::uint32_t>& brightest, double gain) {
    const double black = black_level(sensor), top = max_dn(sensor), range = top - black;
    const int bins = int(top) + 1;
    if (int(brightest.size()) != bins)
        throw InputError("auto exposure: the histogram has " + std::to_string(brightest.size()) +
                         " bins, the sensor's raw DN " + std::to_string(bins));
    std::uint64_t pixels = 0;
    for (const std::uint32_t count : brightest) pixels += count;
    if (pixels == 0) throw InputError("auto exposure: the histogram counts no pixels");
    double dn = 0.0;
    if (ae.metering == Metering::Percentile) {
        // The histogram of whole DN gives the exact nearest rank.
        const double want = std::ceil(ae.percentile / 100.0 * double(pixels));
        const std::uint64_t rank = std::uint64_t(std::clamp(want, 1.0, double(pixels)));
        std::uint64_t seen = 0;
        int b = 0;
        for (; b < bins - 1; ++b) {
            seen += brightest[std::size_t(b)];
            if (seen >= rank) break;
        }
        dn = double(b);
    } else {
        // Whole numbers: the sum is exact (below 2^53), in any order.
        double sum = 0.0;
        for (int b = 0; b < bins; ++b) sum += double(b) * double(brightest[std::size_t(b)]);
        dn = sum / double(pixels);
    }
    ExposureReading r;
    r.level = std::max(0.0, (dn - black) / range);
    r.clip_level = std::min(range, gain * sensor.full_well) / range;
    r.saturated = r.level >= kSaturatedFraction * r.clip_level;
    return r;
}

ExposureReading meter_exposure(const AutoExposure& ae, const Sensor& sensor, const Image& raw,
                               double gain) {
    if (raw.empty() || raw.channels != 3)
        throw InputError(
            "auto exposure: it meters the raw layer (3 channels of DN); apply the camera stage "
            "with CameraLayerSet::raw or CameraLayerSet::meter");
    const std::size_t pixels = std::size_t(raw.width) * raw.height;
    const float* v = raw.data.data();
    const int bins = int(max_dn(sensor)) + 1;
    std::vector<std::uint32_t> hist(std::size_t(bins), 0);
    // Per pixel its brightest channel. Whole numbers convert exactly (no lround, a library call
    // per pixel); out-of-range and NaN values (not from the stage) land in the end bins.
    const float last = float(bins - 1);
    for (std::size_t i = 0; i < pixels; ++i) {
        const float b = std::max(v[3 * i], std::max(v[3 * i + 1], v[3 * i + 2]));
        ++hist[std::size_t(b > 0.0f ? (b < last ? b + 0.5f : last) : 0.0f)];
    }
    return meter_exposure(ae, sensor, hist, gain);
}

ExposureReading meter_exposure(const CameraModel& model, const CameraOutput& frame) {
    if (!frame.brightest.empty())
        return meter_exposure(model.auto_exposure, model.sensor, frame.brightest,
                              frame.exposure.system_gain);
    return meter_exposure(model.auto_exposure, model.sensor, frame.raw, frame.exposure.system_gain);
}

FrameExposure split_exposure(double product, const ExposureLimits& l) {
    const double x = std::clamp(product, l.min_exposure_time_ms * l.min_system_gain,
                                l.max_exposure_time_ms * l.max_system_gain);
    // Gain stays exactly at its minimum until the time is at its maximum (no x / t rounding).
    if (x < l.max_exposure_time_ms * l.min_system_gain)
        return {std::clamp(x / l.min_system_gain, l.min_exposure_time_ms, l.max_exposure_time_ms),
                l.min_system_gain};
    return {l.max_exposure_time_ms,
            std::clamp(x / l.max_exposure_time_ms, l.min_system_gain, l.max_system_gain)};
}

FrameExposure first_exposure(const CameraModel& model) {
    const FrameExposure sensor{model.sensor.exposure_time_ms, system_gain(model.sensor)};
    if (!model.auto_exposure.enabled) return sensor;
    const ExposureLimits l = exposure_limits(model.auto_exposure, model.sensor);
    return {std::clamp(sensor.exposure_time_ms, l.min_exposure_time_ms, l.max_exposure_time_ms),
            std::clamp(sensor.system_gain, l.min_system_gain, l.max_system_gain)};
}

FrameExposure next_exposure(const AutoExposure& ae, const ExposureLimits& limits,
                            const FrameExposure& current, const ExposureReading& reading) {
    const double target = reachable_target(ae.target, reading.clip_level);
    const double level = std::max(reading.level, kMinMeteredLevel);
    // Saturated: the level is a lower bound, so the whole step down cannot pass the target
    // (real cameras reduce a clipped exposure at once too); otherwise a damped step.
    const double d = reading.saturated ? 1.0 : ae.damping;
    const double x = current.exposure_time_ms * current.system_gain;
    return split_exposure(x * std::exp(d * std::log(target / level)), limits);
}

FrameExposure next_exposure(const CameraModel& model, const CameraOutput& frame) {
    const AutoExposure& ae = model.auto_exposure;
    if (!ae.enabled) return first_exposure(model);
    return next_exposure(ae, exposure_limits(ae, model.sensor), frame.exposure,
                         meter_exposure(model, frame));
}

int settle_frames(const AutoExposure& ae, double step, double tolerance, double clip_level) {
    const double target = reachable_target(ae.target, clip_level);
    const double e = std::fabs(std::log(step));
    if (e <= tolerance) return 0;
    if (step > 1.0 && target * step >= kSaturatedFraction * clip_level) {
        const double a = std::log(clip_level / target);
        return std::max(1, int(std::floor(e / a)) + damped_frames(ae.damping, a, tolerance));
    }
    return damped_frames(ae.damping, e, tolerance);
}

}  // namespace deepsea
