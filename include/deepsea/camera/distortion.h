#pragma once
/// \file Lens distortion (docs/camera.md, "Distortion"): OpenCV's Brown-Conrady model, its
/// inverse, the check that it does not fold the image over, and the resampling of a rendered
/// (pinhole, undistorted) image into the distorted one a real lens records.

#include <cstdint>
#include <vector>

#include "deepsea/camera/model.h"
#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/camera.h"

namespace deepsea {

/// Where the ray (x, y, 1) lands, in normalised coordinates (cv::projectPoints' distortion
/// step; pixel = (fx xd + cx, fy yd + cy)).
template <class F>
void distort(const Distortion& d, F x, F y, F& xd, F& yd) {
    const F r2 = x * x + y * y;
    const F radial = F(1) + r2 * (F(d.k1) + r2 * (F(d.k2) + r2 * F(d.k3)));
    xd = x * radial + F(2 * d.p1) * x * y + F(d.p2) * (r2 + F(2) * x * x);
    yd = y * radial + F(d.p1) * (r2 + F(2) * y * y) + F(2 * d.p2) * x * y;
}

/// The ray (x, y, 1) that lands at normalised (xd, yd): Newton's method on distort() from
/// (xd, yd), to 1e-12. False if it did not converge (the distortion folds there).
bool undistort(const Distortion& d, double xd, double yd, double& x, double& y);

/// Throws SchemaError "camera.lens.distortion: ..." (one line) when the distortion folds the
/// image over: the radial mapping r -> r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing before
/// it reaches the image's farthest corner (its outer pixel edges), or a recorded pixel has no
/// ray that lands on it. Undistorted rays and the image's field come from `camera`.
void check_distortion(const Distortion& d, const Camera& camera);

/// For every recorded pixel, where it lies in the rendered pinhole image, and the bilinear
/// resampling that reads it there. Built once per camera (Newton per pixel).
class DistortionMap {
public:
    /// check_distortion, then every pixel's source. An empty map for no distortion.
    DistortionMap(const Camera& camera, const Distortion& d);

    bool empty() const { return m_taps.empty(); }
    /// Where recorded pixel (u, v) lies in the rendered image, pixels (unclamped: with barrel
    /// distortion the corners lie outside it).
    void source(int u, int v, double& su, double& sv) const;
    /// Share of recorded pixels whose source lies outside the rendered image (those repeat
    /// its edge: render a wider pinhole image to avoid it).
    double outside_fraction() const { return m_outside; }

    /// Row v of the recorded image: each pixel bilinearly interpolated from `src` (3 channels,
    /// the camera's size) at its source, clamped to the image (edge pixels repeat).
    void resample_row(const Image& src, int v, float* dst_rgb) const;
    /// The whole recorded image (dst resized to src's size), rows in parallel.
    void resample(const Image& src, Image& dst, const Parallel& par = {}) const;

private:
    /// Top-left tap's pixel index (clamped so the 2x2 taps lie inside) and its weights.
    struct Tap {
        std::uint32_t index;
        float wx, wy;
    };
    Camera m_camera;
    Distortion m_d;
    std::vector<Tap> m_taps;
    double m_outside = 0.0;
};

}  // namespace deepsea
