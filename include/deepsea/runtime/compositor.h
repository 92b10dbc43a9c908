#pragma once
/// \file The runtime compositor: RGB-D frame in, deep-sea layers out (docs/runtime.md).

#include <memory>
#include <optional>
#include <vector>

#include "deepsea/core/frame.h"
#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/water.h"
#include "deepsea/runtime/forward_blur.h"
#include "deepsea/runtime/forward_psf_blur.h"
#include "deepsea/runtime/layers.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// Composites frames of one camera. Keeps its scratch buffers, so after the first frame of a
/// size nothing is allocated. Output is identical at any thread count (rows are independent).
class Compositor {
public:
    /// The sources must outlive the compositor.
    Compositor(const Camera& camera, const Water& water, const IrradianceSource& lamps,
               const BackscatterSource& backscatter);

    /// Fills the layers of dst that `set` names. Throws InputError when the frame does not
    /// match the camera.
    void composite(Layers& dst, const Frame& frame, LayerSet set = LayerSet::All);

private:
    Camera m_camera;
    Water m_water;
    const IrradianceSource& m_lamps;
    const BackscatterSource& m_backscatter;
    ForwardBlur m_blur;                        ///< Jaffe-McGlamery forward scatter
    std::optional<ForwardPsfBlur> m_psf_blur;  ///< forward scatter from the phase function
    std::vector<float> m_rx;                   ///< (u - cx) / fx per column
    Image m_d2;       ///< camera-to-surface distance per pixel, metres (0 for open water)
    Image m_surface;  ///< surface radiance J/pi E (forward scatter on): what the blur spreads
};

}  // namespace deepsea
