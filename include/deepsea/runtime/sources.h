#pragma once
/// \file The compositor's two light sources, behind small interfaces (docs/architecture.md):
/// "how much lamp light reaches this surface point" and "how much water light is added along
/// this ray". Analytic lamps and the baked backscatter asset implement them today; baked
/// multiple-scattering fields can replace either without touching the compositor.

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

struct BackscatterRowBounds;

/// One image row's surface geometry in structure-of-arrays form (camera frame, metres).
struct RowGeometry {
    int v = 0;                 ///< image row
    int n = 0;                 ///< pixels in the row
    const float* x = nullptr;  ///< surface point P
    const float* y = nullptr;
    const float* z = nullptr;   ///< planar depth; open water where !(z > 0) or inf
    const float* nx = nullptr;  ///< unit normal facing the camera
    const float* ny = nullptr;
    const float* nz = nullptr;
};

/// Lamp light arriving at surface points: E = sum_l I_l(theta_l) exp(-c d1) / d1^2 max(0, n.w_l),
/// W/m^2 per channel, written planar as out[c * n + u]. Zero for open water.
class IrradianceSource {
public:
    virtual ~IrradianceSource() = default;
    virtual void irradiance_row(const RowGeometry& row, float* out_rgb_planar) const = 0;
    /// Called by the compositor once per frame before its rows, with the frame's camera and
    /// planar depth (open water where has_surface says so): a source may share work between
    /// rows here. One frame at a time per source. The default does nothing.
    virtual void begin_frame(const Camera& camera, const Image& zdepth) const {}
};

/// Water light added along pixel rays up to planar depth z (z_max for open water), radiance
/// per channel, written interleaved as out[3 * u + c] (as the image's rows hold it).
class BackscatterSource {
public:
    virtual ~BackscatterSource() = default;
    virtual void backscatter_row(int v, int n, const float* z, float* out_rgb) const = 0;
    /// B of `count` pixels (columns cols[i], increasing) of row v, n pixels long, written to
    /// their places in out_rgb (others untouched): for pixels between looked-up rows that
    /// row_bounds does not let the compositor interpolate. The default looks the row up.
    virtual void backscatter_pixels(int v, int n, const float* z, int count, const int* cols,
                                    float* out_rgb) const;
    /// When rows between looked-up rows may be interpolated (backscatter_rows.h: the bound on
    /// the error that B's smoothness in the source allows), or nullptr: never. The default.
    virtual const BackscatterRowBounds* row_bounds() const { return nullptr; }
};

}  // namespace deepsea
