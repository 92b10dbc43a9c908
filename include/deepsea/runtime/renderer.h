#pragma once
/// \file The front door to rendering frames: a baked asset in, deep-sea layers out. The one
/// place that wires the asset's lamps (with the scattered light a multiple-scattering bake
/// stores), its backscatter for the frames' camera and the compositor, and remakes the
/// per-size state when the frames' size changes. The CLI's render (one frame and sequences),
/// the Python module and bench all render through it.

#include <memory>
#include <optional>

#include "deepsea/asset/asset.h"
#include "deepsea/core/frame.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/shadow.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/frame_view.h"
#include "deepsea/runtime/lamp_shadows.h"
#include "deepsea/runtime/layers.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea {

/// How a Renderer renders, beyond what the asset fixes.
struct RenderSettings {
    /// The frames' camera. Width 0 (the default): the asset's, scaled to each frame's size
    /// (frame_camera); otherwise it must see what the asset's camera sees.
    Camera camera;
    /// Forward scatter, where the asset's water has it.
    bool forward = true;
    /// Lamp shadows from the depth map (docs/snow-shadows.md, "Lamp shadows"): off by default, as
    /// in the paper's model; thickness in metres of planar depth.
    bool shadows = false;
    double shadow_thickness = kDefaultShadowThickness;
    /// Pixels between the swept samples (ShadowSettings::step, >= 1).
    int shadow_step = kDefaultShadowStep;
    /// The housing's port (docs/ports.md): each pixel sees along its water-side ray, and the
    /// layers gain `mask`. Unset: the pinhole looks into the water. An asset baked through a
    /// port needs the same port (same_rays); a pinhole asset takes any.
    std::optional<Port> port;
    /// Marine snow (docs/snow-shadows.md, "Marine snow"): unset, none. With it, final holds the
    /// snow and LayerSet::All fills the layers snow and snow_id. Not through a port (refused).
    std::optional<SnowSettings> snow;
};

/// Renders frames with one asset. Keeps the compositor and its buffers between frames of one
/// size; a frame of another size remakes them. One frame at a time (not thread-safe); its
/// output is a function of that frame, the asset and the settings only.
class Renderer {
public:
    /// The asset must outlive the renderer (a temporary asset is refused at compile time).
    /// With a port, its rays are traced here for the settings' camera (or the asset's):
    /// SchemaError for a port that camera cannot look through (validate, check_port_view),
    /// ConfigError for one through which no pixel sees the frame (PortRays), AssetError when
    /// the asset was baked through another port or the settings have none (check_port), before
    /// any frame.
    explicit Renderer(const Asset& asset, RenderSettings settings = {});
    Renderer(Asset&&, RenderSettings = {}) = delete;
    ~Renderer();
    Renderer(Renderer&&) noexcept;
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;
    Renderer& operator=(Renderer&&) = delete;

    /// Fills the layers of `dst` that `set` names for the frame in the caller's memory
    /// (frame_view.h): the colour is read where it lies, row by row; the depth is copied once
    /// (made planar when it is range). InputError naming "colour view" or "depth view" for a
    /// view that checked() refuses, for non-finite float colour, and when colour and depth
    /// differ in size; AssetError when the asset's camera cannot take the frame's size
    /// (another aspect ratio).
    void render(Layers& dst, const ColorView& color, const DepthView& depth,
                LayerSet set = LayerSet::All);
    /// The image only, each row handed to `rows` as it is finished (FinalRows).
    void render(Layers& dst, const ColorView& color, const DepthView& depth, const FinalRows& rows);

    /// The same for an owned frame (as io reads files) whose depth is `kind`: range depth is
    /// converted to planar z in place.
    void render(Layers& dst, Frame& frame, LayerSet set = LayerSet::All,
                DepthKind kind = DepthKind::Z);
    void render(Layers& dst, Frame& frame, const FinalRows& rows, DepthKind kind = DepthKind::Z);

    /// Makes the compositor for frames of width x height now rather than at the first such
    /// frame (a sequence makes it while its first frames are read). The same errors as a
    /// frame of that size would meet; a frame of another size later remakes it.
    void prepare(int width, int height);

    /// The next frames' key and, where known, camera pose (camera to world), for marine snow:
    /// with a pose its particles stay fixed in the world; without one they are drawn afresh
    /// for each key. With the snow's streaks on, a pose and the frame's shutter poses
    /// (camera_motion.h), each particle is drawn as a motion streak. Without a call: key 0, no
    /// pose.
    void set_frame(std::uint64_t frame_key, std::optional<CameraPose> pose = {},
                   std::optional<Shutter> shutter = {});
    /// Marine snow particles drawn in the last frame (0 without snow).
    int snow_drawn() const;

    /// The camera of the last frame's size; before any frame, the settings' or the asset's.
    const Camera& camera() const;
    /// The water as rendered (the asset's, forward scatter off where the settings say so).
    const Water& water() const;

private:
    struct State;
    std::unique_ptr<State> m;
};

}  // namespace deepsea
