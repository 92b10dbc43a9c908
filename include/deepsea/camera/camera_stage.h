#pragma once
/// \file The camera stage (docs/camera.md): a frame's radiance layer in, what a real camera
/// records out. Between the renderer (radiance layers) and the writer:
///
///     deepsea::CameraStage stage(model, intrinsics);   // checks the model, builds the lens map
///     deepsea::CameraOutput out;
///     stage.apply(out, layers.final, frame_index);     // out.image: display values in [0, 1]
///
/// A frame's noise depends only on (sensor.seed, frame_key, pixel): frames can be made alone, in
/// any order, at any thread count, with the same bits.

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "deepsea/camera/distortion.h"
#include "deepsea/camera/model.h"
#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"

namespace deepsea {

/// The settings an exposure controller changes from frame to frame (the model's by default).
struct FrameExposure {
    double exposure_time_ms = 0.0;  ///< > 0
    double system_gain = 0.0;       ///< K, DN per electron, > 0
};

/// The layers a stage fills besides the image; the others are left empty (no memory).
struct CameraLayerSet {
    bool raw = false;         ///< CameraOutput::raw
    bool linear_dn = false;   ///< CameraOutput::linear_dn
    bool noise_free = false;  ///< CameraOutput::noise_free
    /// The image as 8-bit codes in CameraOutput::codes8 instead of display values in
    /// CameraOutput::image (left empty): what a PNG or JPEG writer stores, made in the stage
    /// while each row is in cache (no float image written and read again).
    bool codes8 = false;
    /// CameraOutput::brightest, what auto exposure meters, without keeping the raw layer.
    bool meter = false;

    static CameraLayerSet all() { return {true, true, true}; }
};

/// One recorded frame. Images are 3 channels (R, G, B), rows top to bottom, the camera's size.
struct CameraOutput {
    /// Display values in [0, 1] after white balance, matrix and the output curve: what an 8- or
    /// 16-bit writer quantises (round(value * (2^bits - 1))) without another curve.
    Image image;
    /// With CameraLayerSet::codes8, the image instead: 3 x width x height codes, interleaved,
    /// rows top to bottom, each trunc(min(max(value, 0), 1) x 255 + 0.5): the codes the
    /// 8-bit writers make of `image` (io's encode_display), bit for bit.
    std::vector<std::uint8_t> codes8;
    int width = 0, height = 0;  ///< the frame's size (the camera's), set by apply
    /// DN as the sensor reads them out: with noise, clipped at the full well and to
    /// [0, 2^bits - 1], quantised (whole numbers held in floats).
    Image raw;
    /// DN with all noise, before the full-well and DN clipping and before quantisation:
    /// K (electrons + DSNU + read noise) + black level.
    Image linear_dn;
    /// Display values of the same frame without any noise (temporal or fixed pattern):
    /// K min(mean electrons, full well) + black level, clipped to the DN range, not quantised,
    /// processed as the image (same white-balance gains). The target a denoiser learns.
    Image noise_free;
    /// With CameraLayerSet::meter: entry d counts the pixels whose brightest channel reads out d
    /// raw DN (0 to 2^bits - 1), counted row by row as they are recorded (integer sums: the
    /// same at any thread count). What meter_exposure reads instead of `raw`.
    std::vector<std::uint32_t> brightest;
    FrameExposure exposure;            ///< the settings this frame was recorded with
    Rgb white_balance{1.0, 1.0, 1.0};  ///< the gains applied (grey world's, per frame)
};

/// A camera model fixed to intrinsics: validated once; its lens map and its pixels' fixed
/// response (falloff x PRNU, and DSNU: 8 bytes per pixel and channel, 15 MB at 800 x 800)
/// built once; apply() is const and may run for several frames at once from different
/// threads (each its own output).
namespace camera_rows {
struct DisplayTables;  // every whole DN's display value and 8-bit code (src/camera)
}

class CameraStage {
public:
    /// validate(model), validate(intrinsics) (optics/schema.h) and check_distortion: throws
    /// SchemaError (a ConfigError) naming the first key out of range. With the housing's `port`
    /// (docs/ports.md, "Radiance across the interfaces") each pixel's irradiance takes
    /// port_radiance_factor of its ray (the n^2 law, Fresnel where the port asks), built once
    /// into the pixels' response like vignetting (validate, check_port_view first).
    CameraStage(const CameraModel& model, const Camera& intrinsics,
                const std::optional<Port>& port = {});

    const CameraModel& model() const { return m_model; }
    const Camera& camera() const { return m_camera; }
    const DistortionMap& distortion() const { return m_map; }
    const std::optional<Port>& port() const { return m_port; }
    /// The port's radiance factor of pixel (u, v), channel c (1 without a port): what the
    /// stage multiplies the pixel's radiance by.
    float port_factor(int u, int v, int c) const;
    /// The model's exposure time and system gain.
    FrameExposure default_exposure() const;
    /// Mean photo-electrons per unit radiance (1 W/(m^2 sr)) on the axis, channel c, at an
    /// exposure time: what an exposure controller scales.
    double electrons_per_radiance(int channel, double exposure_time_ms) const;

    /// Records `radiance` (linear RGB W/(m^2 sr), 3 channels, the intrinsics' size: InputError
    /// otherwise) as frame `frame_key` with the model's exposure, into `out` (its images
    /// reused when they have the size). Rows in parallel (par.threads; the same bits at any).
    void apply(CameraOutput& out, const Image& radiance, std::uint64_t frame_key,
               CameraLayerSet layers = {}, const Parallel& par = {}) const;
    /// The same with this frame's exposure (SchemaError naming camera.sensor.exposure_time_ms
    /// or camera.sensor.system_gain for a value out of range).
    void apply(CameraOutput& out, const Image& radiance, std::uint64_t frame_key,
               const FrameExposure& exposure, CameraLayerSet layers = {},
               const Parallel& par = {}) const;

    /// Radiance rows as a renderer hands them over (runtime's FinalRows): row v's 3 x width
    /// values, valid during the call; from several threads, each row once, in any order.
    using RadianceRows = std::function<void(int v, const float* rgb)>;
    /// Whether apply_rows can record this stage's frames: no lens distortion, grey world or
    /// Bayer mosaic (each needs the whole frame's radiance or raw DN before any row is done).
    bool records_rows() const;
    /// apply() with the radiance handed over row by row, so that no radiance frame is written
    /// and read again: calls `render` once with the rows' receiver, which records each row
    /// into `out` as it comes. The same bits as apply() on the whole frame. InputError when
    /// !records_rows() or when `render` hands over a row outside the camera's.
    void apply_rows(CameraOutput& out, const std::function<void(const RadianceRows&)>& render,
                    std::uint64_t frame_key, const FrameExposure& exposure,
                    CameraLayerSet layers = {}) const;

private:
    struct Recording;  // one frame's settings and tables (camera_stage.cpp)

    CameraModel m_model;
    Camera m_camera;
    DistortionMap m_map;
    std::optional<Port> m_port;
    // 64-byte aligned arrays: per column ray_x(u)^2; per value (3 x width x height) the mean
    // electrons per unit radiance and millisecond (falloff, channel response, PRNU) and the
    // DSNU in electrons (null without DSNU); per value the port's radiance factor (null
    // without a port), already in m_response.
    std::shared_ptr<const float> m_x2, m_response, m_dsnu, m_port_factor;
    // Where a frame's image comes from a table of every DN and the table depends on the model
    // alone (no grey world: its gains are the frame's), the table, made once here instead of
    // per frame (null otherwise).
    std::shared_ptr<const camera_rows::DisplayTables> m_tables;
};

}  // namespace deepsea
