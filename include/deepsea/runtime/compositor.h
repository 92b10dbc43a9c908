#pragma once
/// \file The runtime compositor: RGB-D frame in, deep-sea layers out (docs/runtime.md).

#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "deepsea/core/frame.h"
#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/forward_blur.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "deepsea/runtime/frame_view.h"
#include "deepsea/runtime/layers.h"
#include "deepsea/runtime/port_rays.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

struct ForwardPsfTable;

/// Composites frames of one camera. Keeps its scratch buffers, so after the first frame of a
/// size nothing is allocated. Output is identical at any thread count (rows are independent).
class Compositor {
public:
    /// The sources must outlive the compositor. With `port` (which must outlive it too, and
    /// whose camera must be `camera`), each pixel sees along its water-side ray through the
    /// housing's port (docs/ports.md): the frame is where those rays meet, the backscatter
    /// source takes each pixel's hit as the planar depth of the hit point (PortBackscatter),
    /// and the layers gain `mask`. With `forward_table` (an asset's forward scatter from
    /// transport, optics/forward_transport.h) the phase-function forward scatter blurs with its
    /// point spread instead of the small-angle model's; it is read only here.
    Compositor(const Camera& camera, const Water& water, const IrradianceSource& lamps,
               const BackscatterSource& backscatter, const PortRays* port = nullptr,
               const ForwardPsfTable* forward_table = nullptr);

    /// Fills the layers of dst that `set` names from a checked colour view (frame_view.h) and
    /// planar depth in metres. Throws InputError when the frame does not match the camera.
    void composite(Layers& dst, const ColorView& color, const Image& depth,
                   LayerSet set = LayerSet::All);
    void composite(Layers& dst, const Frame& frame, LayerSet set = LayerSet::All);

    using FinalRows = deepsea::FinalRows;

    /// The image only, each row handed to `rows` as it is finished instead of being kept (a
    /// sequence encodes it there, while the row is in cache). The same values as the final
    /// layer of composite(). dst is scratch: nothing of the image is kept, and its layers are
    /// freed.
    void composite(Layers& dst, const ColorView& color, const Image& depth, const FinalRows& rows);
    void composite(Layers& dst, const Frame& frame, const FinalRows& rows);

    /// Exact: the compositor's bounded approximations off (docs/runtime.md, "Bounded
    /// approximations"): the forward scatter's block distances (ForwardPsfBlur::
    /// set_block_distances) and, for the image alone, the direct signal's transmission from the
    /// point spread's table (ForwardPsfBlur::add_direct_row) and the backscatter of rows
    /// between looked-up rows (BackscatterSource::row_bounds). The path the tests hold them
    /// against. Off by default.
    void set_exact(bool exact);
    /// The forward scatter's lean on surfaces tilted to the ray (transport tables, not through
    /// a port: docs/forward-lean.md). On by default; off: the facing plane's symmetric kernel
    /// everywhere, as assets were rendered before it.
    void set_forward_lean(bool on) { m_forward_lean = on; }

private:
    void run(Layers& dst, const ColorView& color, const Image& depth, LayerSet set,
             const FinalRows* rows);
    /// Pixels per radian of the rays in the water (the forward blur's scale): fx, or the
    /// port's water_fx.
    double forward_fx() const;

    Camera m_camera;
    Water m_water;
    bool m_exact = false;        ///< set_exact
    bool m_forward_lean = true;  ///< set_forward_lean
    const IrradianceSource& m_lamps;
    const BackscatterSource& m_backscatter;
    ForwardBlur m_blur;                        ///< Jaffe-McGlamery forward scatter
    std::optional<ForwardPsfBlur> m_psf_blur;  ///< forward scatter from the phase function
    EdgeFalloff m_beyond;                      ///< its scene beyond the frame (transport tables)
    std::vector<float> m_rx;                   ///< (u - cx) / fx per column
    std::vector<float> m_c3;                   ///< c per channel, as a row holds it (3 x width)
    // With forward scatter on (without, rows keep their own):
    Image m_d2;       ///< camera-to-surface distance per pixel, metres (0 for open water)
    Image m_surface;  ///< surface radiance J/pi E: what the blur spreads
    Image m_lean;     ///< the forward kernel's lean per pixel (forward_lean), 2 channels
    std::vector<float> m_row_far;  ///< each row's largest d2 (the point spread's table length)
    // The image alone with its approximations: the looked-up rows' B and sanitised depth.
    Image m_back, m_back_z;
    // Through a port:
    const PortRays* m_port = nullptr;
    Image m_in_surface;  ///< the frame's normal and linear colour per input pixel (port_warp.h)
    Image m_inv_depth;   ///< the frame's inverse depth (optics' inverse_depth)
    Image m_nearest, m_nearest_rows;  ///< its window_nearest (port_rays.h), the blocks' maxima
    Image m_window_rows;              ///< its window_row_maxima, a row each
    std::vector<float> m_row_near;    ///< each row's nearest surface depth (+inf: none)
    Image m_hit_z;  ///< planar depth of each output pixel's hit (forward scatter's pass)
};

}  // namespace deepsea
