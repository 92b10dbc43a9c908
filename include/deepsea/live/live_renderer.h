#pragma once
/// \file Live rendering for a robot middleware (docs/ros.md): paired colour and depth views in,
/// the exposed image and the optional layers out as the 8-bit and float buffers an image
/// message carries. It renders through the front door (Renderer: the asset's camera rescaled
/// to each frame's size, per-size state remade on a change) and, with a camera model, the
/// camera stage. No middleware headers: the ROS 1 node and a ROS 2 port call it unchanged.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/asset/asset.h"
#include "deepsea/camera/model.h"
#include "deepsea/optics/camera.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/frame_view.h"
#include "deepsea/runtime/renderer.h"

namespace deepsea {

/// What a LiveRenderer renders and publishes.
struct LiveSettings {
    RenderSettings render;  ///< forward scatter, shadows, snow, the frames' camera
    /// Automatic (the default): chosen on the first frame rendered, as `deepsea render` does
    /// for a sequence, then kept; else the fixed factor. Not with a camera model.
    Exposure exposure;
    /// The camera stage (docs/camera.md): with it the image is what that camera records (its
    /// own exposure time and gain; frame keys from the caller), and noise_free is on offer.
    std::optional<CameraModel> camera_model;
    bool backscatter = false;  ///< the backscatter layer, exposed and sRGB-encoded as the image
    bool noise_free = false;   ///< the camera stage's noise-free image (needs camera_model)
    bool depth = false;        ///< planar depth in metres (0: open water), 32-bit float
};

/// One rendered frame: row-major, top row first, packed (3 x width bytes a row).
struct LiveFrame {
    int width = 0, height = 0;
    Camera camera;                          ///< the frame's intrinsics (for camera_info)
    std::vector<std::uint8_t> image;        ///< rgb8
    std::vector<std::uint8_t> backscatter;  ///< rgb8, when asked
    std::vector<std::uint8_t> noise_free;   ///< rgb8, when asked
    std::vector<float> depth;               ///< 32FC1, when asked
    double exposure = 0.0;                  ///< the factor used (0 with a camera model)
};

/// Renders frame after frame with one asset. One frame at a time (the render thread).
class LiveRenderer {
public:
    /// ConfigError for settings that cannot work (noise_free without a camera model, an
    /// exposure with one), and the Renderer's and CameraStage's own refusals, before any frame.
    LiveRenderer(const Asset& asset, LiveSettings settings);
    LiveRenderer(Asset&&, LiveSettings) = delete;
    ~LiveRenderer();

    /// Renders the pair into `out` (its buffers reused). `frame_key` keys the camera noise and
    /// the marine snow. InputError for views the renderer refuses (sizes differ, ...), AssetError
    /// when the asset's camera cannot take the frame's size; `out` is then left as it was.
    void render(LiveFrame& out, const ColorView& color, const DepthView& depth,
                std::uint64_t frame_key);

    /// Times the per-size state was made (the first frame's size counts as one).
    int sizes_seen() const;
    /// The exposure factor in use (0 before an automatic one is chosen, or with a camera).
    double exposure() const;

private:
    void note_camera();  ///< counts a new frame camera, drops the camera stage made for the last
    struct State;
    std::unique_ptr<State> m;
};

/// "" when the middleware's camera_info (`given`: its size and K) matches what the renderer
/// uses for frames of that size (`expected`) within `rel_tol` of the focal length in pixels;
/// else one line naming the first value that differs and both values.
std::string intrinsics_mismatch(const Camera& expected, const Camera& given, double rel_tol = 1e-3);

/// Passes a problem on once per change: report() is true when `message` differs from the last
/// one passed (an empty message, "all is well", resets it silently), so a stream of frames
/// with the same fault logs one line, and a new fault, or the same after a good spell, logs
/// again.
class ChangeReporter {
public:
    bool report(const std::string& message) {
        if (message == m_last) return false;
        m_last = message;
        return !message.empty();
    }

private:
    std::string m_last;
};

}  // namespace deepsea
