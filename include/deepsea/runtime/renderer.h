#pragma once
/// \file The front door to rendering frames: a baked asset in, deep-sea layers out. The one
/// place that wires the asset's lamps (with the scattered light a multiple-scattering bake
/// stores), its backscatter for the frames' camera and the compositor, and remakes the
/// per-size state when the frames' size changes. The CLI's render (one frame and sequences),
/// the Python module and bench all render through it.

#include <memory>

#include "deepsea/asset/asset.h"
#include "deepsea/core/frame.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "deepsea/runtime/layers.h"

namespace deepsea {

/// How a Renderer renders, beyond what the asset fixes.
struct RenderSettings {
    /// The frames' camera. Width 0 (the default): the asset's, scaled to each frame's size
    /// (frame_camera); otherwise it must see what the asset's camera sees.
    Camera camera;
    /// Forward scatter, where the asset's water has it.
    bool forward = true;
};

/// Renders frames with one asset. Keeps the compositor and its buffers between frames of one
/// size; a frame of another size remakes them. One frame at a time (not thread-safe); its
/// output is a function of that frame, the asset and the settings only.
class Renderer {
public:
    /// The asset must outlive the renderer (a temporary asset is refused at compile time).
    explicit Renderer(const Asset& asset, RenderSettings settings = {});
    Renderer(Asset&&, RenderSettings = {}) = delete;
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Fills the layers of `dst` that `set` names for `frame`, whose depth is `kind` (range
    /// depth is converted to planar z in place). AssetError when the asset's camera cannot
    /// take the frame's size (another aspect ratio), InputError when colour and depth differ.
    void render(Layers& dst, Frame& frame, LayerSet set = LayerSet::All,
                DepthKind kind = DepthKind::Z);
    /// The image only, each row handed to `rows` as it is finished (Compositor::FinalRows).
    void render(Layers& dst, Frame& frame, const Compositor::FinalRows& rows,
                DepthKind kind = DepthKind::Z);

    /// The camera of the last frame's size; before any frame, the settings' or the asset's.
    const Camera& camera() const;
    /// The water as rendered (the asset's, forward scatter off where the settings say so).
    const Water& water() const { return m_water; }

private:
    /// The compositor for `frame`'s size, its depth made planar.
    Compositor& prepare(Frame& frame, DepthKind kind);

    const Asset& m_asset;
    RenderSettings m_settings;
    Water m_water;
    AnalyticLamps m_lamps;
    Camera m_camera;  ///< the compositor's (width 0 before the first frame)
    std::unique_ptr<AssetBackscatter> m_backscatter;
    std::unique_ptr<Compositor> m_compositor;
};

}  // namespace deepsea
