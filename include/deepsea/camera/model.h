#pragma once
/// \file The camera that records a frame's radiance (docs/camera.md): lens, sensor and
/// processing as plain structs, with units and defaults, and the one range check of every
/// value. Field names are the config keys (`camera.lens.f_number`, ...), so an error names the
/// key the user typed.
///
/// What the model leaves out (docs/camera.md, "Left out"): the lens's magnification term
/// (1 + m)^2 (objects far compared with the focal length), stray light and flare, the port's
/// n^2 radiance law, defocus and diffraction, chromatic aberration, a Bayer mosaic and its
/// demosaic (each pixel records R, G and B, as three co-sited photosites), spectral integration
/// (each channel is one mean wavelength), the sensor's non-linearity, dark current's growth
/// with temperature and its pixel-to-pixel spread, defect and hot pixels, row and column
/// noise, blooming and the rolling shutter. The auto-exposure controller that acts on its
/// settings (AutoExposure, below) is in auto_exposure.h.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/snow.h"

namespace deepsea {

/// OpenCV's Brown-Conrady lens distortion (cv::projectPoints' k1, k2, p1, p2, k3: same signs,
/// same normalisation). With (x, y) = (X/Z, Y/Z) and r^2 = x^2 + y^2, a ray lands at
///   x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
///   y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
/// and pixel (fx x' + cx, fy y' + cy). All zero (the default): a pinhole.
struct Distortion {
    double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;

    bool enabled() const { return k1 != 0.0 || k2 != 0.0 || p1 != 0.0 || p2 != 0.0 || k3 != 0.0; }
};

/// Irradiance falloff over the image: the natural cos^4 of the field angle times an optional
/// measured polynomial 1 + k1 r^2 + k2 r^4 + k3 r^6, with r^2 = x^2 + y^2 in the same
/// normalised coordinates as Distortion (x = (u - cx)/fx of the recorded pixel: r = tan of the
/// field angle), not a fraction of the image's diagonal.
struct Vignetting {
    bool natural = true;  ///< cos^4(theta) of the pinhole geometry
    double k1 = 0.0, k2 = 0.0, k3 = 0.0;

    bool polynomial() const { return k1 != 0.0 || k2 != 0.0 || k3 != 0.0; }
};

/// What lies between the water and the sensor.
struct Lens {
    double f_number = 2.8;       ///< N, > 0 (image-space: the lens's focal ratio)
    double transmittance = 0.9;  ///< T in (0, 1]: lens (and port window) transmission
    /// Distance the lens is focused at, metres, > 0: marine snow's defocus (optics/snow.h).
    double focus_distance_m = kDefaultFocusDistance;
    Vignetting vignetting;
    Distortion distortion;
};

/// A colour filter array: which channel each photosite records, named by its 2 x 2 tile read
/// left to right, top to bottom from pixel (0, 0) (docs/bayer.md). None: every
/// pixel records R, G and B (three co-sited photosites).
enum class BayerPattern { None, Rggb, Bggr, Grbg, Gbrg };

/// The sensor as EMVA 1288 (release 4.0) describes it. The defaults are round values typical
/// of a modern 12-bit colour CMOS machine-vision sensor with 3.45 um pixels (the class of Sony
/// IMX264/IMX250), not a particular camera's datasheet.
struct Sensor {
    double pixel_pitch_um = 3.45;    ///< square pixels; the light-sensitive area is pitch^2
    double exposure_time_ms = 10.0;  ///< > 0
    /// eta per channel (electrons per photon on the pixel area; a fill factor is part of it).
    Rgb quantum_efficiency{0.50, 0.60, 0.50};
    /// Mean wavelength per channel, nm: each channel's photons are counted at this one
    /// wavelength (deepsea's bands: R 600-700, G 500-600, B 400-500 nm).
    Rgb wavelength_nm{650.0, 550.0, 450.0};
    /// System gain K, DN per electron. Unset: from `iso`.
    std::optional<double> system_gain;
    /// Used when system_gain is unset: K = (iso / 100) (2^bits - 1 - black_level) / full_well,
    /// so that at ISO 100 the full well just fills the DN range ("unity" ISO), and each
    /// doubling of ISO doubles K (and halves the electrons that saturate the output).
    double iso = 100.0;
    double full_well = 10000.0;  ///< saturation capacity, electrons, >= 1
    int bits = 12;               ///< 8 to 16: DN in [0, 2^bits - 1]
    /// Offset added to every DN before quantisation, so that dark noise is not clipped at 0.
    /// Unset: 2^(bits - 6) (1/64 of the range: 64 DN at 12 bits).
    std::optional<double> black_level;
    double dark_noise = 2.5;    ///< sigma_d: read noise, electrons rms
    double dark_current = 1.0;  ///< mu_I: electrons per second (Poisson, with the signal)
    double dsnu = 1.0;          ///< dark signal non-uniformity, electrons rms (fixed pattern)
    double prnu_percent = 0.5;  ///< photo-response non-uniformity, % rms (fixed pattern)
    /// False: no noise at all (no shot, dark, DSNU or PRNU; quantisation stays in `raw`).
    bool noise = true;
    std::uint64_t seed = 0;  ///< one camera: its fixed patterns, and with the frame key, its noise
    /// A colour filter array (each photosite records one channel; the image is demosaiced).
    BayerPattern bayer = BayerPattern::None;
};

/// White balance: none, fixed per-channel gains, or grey world (gains that make the frame's
/// mean R, G and B equal to its mean G).
enum class WhiteBalance { None, Gains, GreyWorld };

/// The curve from linear display values to encoded ones.
enum class OutputCurve { Linear, Srgb, Gamma };

/// From DN to display values: x = (DN - black_level) / (2^bits - 1 - black_level), white
/// balance, the camera matrix, clamp to [0, 1], the output curve.
struct Processing {
    WhiteBalance white_balance = WhiteBalance::None;
    Rgb gains{1.0, 1.0, 1.0};  ///< WhiteBalance::Gains: multipliers R, G, B, > 0
    /// Optional 3x3 camera matrix, row-major: out_i = sum_j M_ij in_j, after white balance.
    std::optional<std::array<double, 9>> matrix;
    OutputCurve curve = OutputCurve::Srgb;
    double gamma = 2.2;  ///< OutputCurve::Gamma: encoded = x^(1/gamma), gamma > 0
};

/// What the auto-exposure meter reads from a frame's raw DN (per pixel its brightest channel).
enum class Metering { Mean, Percentile };

/// An auto-exposure controller like a robot camera's (auto_exposure.h, docs/camera.md, "Auto
/// exposure"): from frame to frame of a sequence it moves the exposure time and the system gain
/// so that the metered level reaches `target`, a damped step per frame, within the limits.
/// Exposure time is used first, up to its limit, then gain (as real cameras do: gain adds noise).
struct AutoExposure {
    bool enabled = false;  ///< off: every frame has the sensor's exposure time and gain
    Metering metering = Metering::Percentile;
    double percentile = 99.0;  ///< Metering::Percentile: p in (0, 100], nearest rank
    /// The metered value's target above the black level, as a fraction of the DN range
    /// (2^bits - 1 - black_level), in (0, 1).
    double target = 0.5;
    /// d in (0, 1]: the fraction of the step (in log exposure) to the target taken per frame;
    /// 1 takes it at once.
    double damping = 0.5;
    double min_exposure_time_ms = 0.01;  ///< > 0
    double max_exposure_time_ms = 30.0;  ///< >= min (30 ms fits a 30 frames/s period)
    /// K limits, DN per electron. Unset: the sensor's K (system_gain or iso) and 16 times the
    /// minimum (24 dB of gain).
    std::optional<double> min_system_gain, max_system_gain;
};

/// A camera: what turns radiance into a recorded image.
struct CameraModel {
    Lens lens;
    Sensor sensor;
    Processing processing;
    AutoExposure auto_exposure;
};

/// The system gain K (DN per electron) the sensor's settings give.
double system_gain(const Sensor& sensor);
/// The black level in DN the sensor's settings give.
double black_level(const Sensor& sensor);
/// 2^bits - 1.
double max_dn(const Sensor& sensor);

/// Throws SchemaError (a ConfigError, optics/schema.h) naming the first value out of range as
/// "camera.sensor.full_well: must be >= 1, got 0". Checks every key of the four structs (the
/// auto exposure's also when it is off). A distortion that folds the image over is refused
/// where the intrinsics are known (distortion.h, check_distortion; CameraStage's constructor
/// calls both).
void validate(const CameraModel& model);

/// The keys of each map of the camera model, in the order docs/camera.md lists them: what the
/// YAML reader of `camera: {lens:, sensor:, processing:, auto_exposure:}` will accept.
namespace camera_schema {
inline const std::vector<std::string> kCameraModel = {"lens", "sensor", "processing",
                                                      "auto_exposure"};
inline const std::vector<std::string> kLens = {"f_number", "transmittance", "focus_distance_m",
                                               "vignetting", "distortion"};
inline const std::vector<std::string> kVignetting = {"natural", "k1", "k2", "k3"};
inline const std::vector<std::string> kDistortion = {"k1", "k2", "p1", "p2", "k3"};
inline const std::vector<std::string> kSensor = {"preset",
                                                 "pixel_pitch_um",
                                                 "exposure_time_ms",
                                                 "quantum_efficiency",
                                                 "wavelength_nm",
                                                 "system_gain",
                                                 "iso",
                                                 "full_well",
                                                 "bits",
                                                 "black_level",
                                                 "dark_noise",
                                                 "dark_current",
                                                 "dsnu",
                                                 "prnu_percent",
                                                 "noise",
                                                 "seed",
                                                 "bayer"};
inline const std::vector<std::string> kProcessing = {"white_balance", "matrix", "curve"};
inline const std::vector<std::string> kAutoExposure = {"enabled",
                                                       "metering",
                                                       "target",
                                                       "damping",
                                                       "min_exposure_time_ms",
                                                       "max_exposure_time_ms",
                                                       "min_system_gain",
                                                       "max_system_gain"};
}  // namespace camera_schema

}  // namespace deepsea
