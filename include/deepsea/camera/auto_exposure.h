#pragma once
/// \file The auto-exposure controller (docs/camera.md, "Auto exposure"): meter a recorded
/// frame's raw DN, step the exposure toward the target, split it into exposure time and gain.
/// Pure functions: the controller's whole state is the FrameExposure a frame was recorded with
/// (CameraOutput::exposure), so a sequence records it per frame and can resume from any frame
/// with the same bits. Frame k+1's settings need frame k, so a sequence runs it serially:
///
///     deepsea::FrameExposure e = deepsea::first_exposure(model);
///     deepsea::CameraLayerSet layers;
///     layers.meter = true;                              // the meter's histogram
///     for (std::uint64_t k = 0; k < frames; ++k) {
///         stage.apply(out, radiance[k], k, e, layers);   // out.exposure == e: record it
///         e = deepsea::next_exposure(model, out);        // frame k + 1's settings
///     }

#include <cstdint>
#include <vector>

#include "deepsea/camera/camera_stage.h"
#include "deepsea/camera/model.h"
#include "deepsea/core/image.h"

namespace deepsea {

/// The limits an AutoExposure keeps to, resolved against the sensor (unset gains: the sensor's
/// K and 16 times it, at most 1e6).
struct ExposureLimits {
    double min_exposure_time_ms = 0.0, max_exposure_time_ms = 0.0;  ///< ms
    double min_system_gain = 0.0, max_system_gain = 0.0;            ///< K, DN per electron
};

/// The settings' limits with the unset gains resolved against the sensor.
ExposureLimits exposure_limits(const AutoExposure& ae, const Sensor& sensor);

/// A metered value at or above this fraction of the clip level counts as saturated.
inline constexpr double kSaturatedFraction = 0.95;
/// The controller's floor under a metered level (a black frame): its log stays finite.
inline constexpr double kMinMeteredLevel = 1e-6;

/// What the meter read from one frame. Levels are DN above the black level as a fraction of
/// the DN range, 2^bits - 1 - black_level.
struct ExposureReading {
    double level = 0.0;  ///< the metered value (percentile or mean), >= 0
    /// Where the frame clips: min(range, K full_well) / range (K the frame's gain): 1 unless
    /// the full well fills before the DN range.
    double clip_level = 1.0;
    /// level >= kSaturatedFraction clip_level: the true level may be higher (level is a lower
    /// bound of it).
    bool saturated = false;
};

/// Meters a frame recorded with system gain K from the histogram of its pixels' brightest raw DN
/// (CameraOutput::brightest: entry d counts the pixels whose brightest of R, G and B reads d):
/// the nearest-rank percentile or the mean, both exact. Deterministic; InputError for a
/// histogram of another size than the sensor's DN range or one that counts no pixels.
ExposureReading meter_exposure(const AutoExposure& ae, const Sensor& sensor,
                               const std::vector<std::uint32_t>& brightest, double system_gain);
/// The same from raw DN (CameraOutput::raw: 3 channels of whole DN), their histogram made first.
/// InputError for an empty or non-RGB image.
ExposureReading meter_exposure(const AutoExposure& ae, const Sensor& sensor, const Image& raw,
                               double system_gain);
/// The same for a frame the stage recorded (its `brightest` histogram, else its raw layer; its
/// exposure's gain).
ExposureReading meter_exposure(const CameraModel& model, const CameraOutput& frame);

/// The settings for an exposure product X = t K (ms DN per electron; the signal in DN is
/// proportional to it), the way real cameras split it: exposure time first, from its minimum
/// to its maximum at the minimum gain, then gain. X beyond the limits' products is clamped.
FrameExposure split_exposure(double product, const ExposureLimits& limits);

/// The first frame's settings: the sensor's exposure time and gain, each clamped to the
/// limits (the sensor's settings unchanged when the controller is off).
FrameExposure first_exposure(const CameraModel& model);

/// One step of the controller: with the target T' = min(T, kSaturatedFraction clip_level) and
/// the level m = max(reading.level, kMinMeteredLevel),
///   ln X' = ln X + d ln(T' / m)   (a saturated reading: d = 1, the whole step down at once)
/// with X = current's t K; then split_exposure. Deterministic (plain double arithmetic).
FrameExposure next_exposure(const AutoExposure& ae, const ExposureLimits& limits,
                            const FrameExposure& current, const ExposureReading& reading);
/// The next frame's settings after `frame` (meter_exposure of its histogram or raw layer, then
/// the step from frame.exposure). The controller off: the sensor's settings. InputError
/// without either.
FrameExposure next_exposure(const CameraModel& model, const CameraOutput& frame);

/// Frames until the metered level is within `tolerance` (|ln(m / T')|) of the target after the
/// scene's brightness changes by `step` (new / old) from a settled frame: frame 0 is the first
/// one of the new brightness, recorded with the old settings. For a meter proportional to the
/// exposure (no noise) and a target exposure within the limits; with e = |ln step|:
///   no saturation:  n = ceil(ln(tolerance / e) / ln(1 - d))   (1 for d = 1; 0 if e <= tol)
///   saturating (step > 1, T' step >= kSaturatedFraction clip_level), with a = ln(clip / T'):
///                   n <= floor(e / a) + ceil(ln(tolerance / a) / ln(1 - d))
/// (each saturated frame steps down by at least a, never past the target). A bound, exact
/// without saturation.
int settle_frames(const AutoExposure& ae, double step, double tolerance, double clip_level = 1.0);

}  // namespace deepsea
