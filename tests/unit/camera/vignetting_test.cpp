// A uniform radiance field shows the natural cos^4 falloff of the pinhole geometry and the
// measured polynomial, to 1e-3, against the falloff written out here from the angle.
#include <gtest/gtest.h>

#include <cmath>

#include "camera_test_util.h"
#include "deepsea/camera/sensor.h"

namespace deepsea {
namespace {

using namespace camera_test;

/// The falloff at every pixel as the stage records it: linear DN over the axis's DN.
void check_falloff(const Vignetting& vig, double tol) {
    CameraModel m;
    m.lens.vignetting = vig;
    m.sensor.noise = false;
    m.sensor.dark_current = 0.0;
    m.sensor.full_well = 1e9;
    m.sensor.system_gain = 1.0;  // DN = electrons + black: float keeps 1e-7 of them
    // Off centre, 44 degrees from the axis at the farthest corner (cos^4 = 0.27).
    const Camera cam{160, 120, 110.0, 100.0, 71.3, 64.8};
    const CameraStage stage(m, cam);
    const Image field = flat(cam.width, cam.height, Rgb(0.01, 0.02, 0.03));
    CameraOutput out;
    CameraLayerSet set;
    set.linear_dn = true;
    stage.apply(out, field, 0, set);
    const double K = system_gain(m.sensor), black = black_level(m.sensor);
    double smallest = 1.0;
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            // Written out from the geometry: tan(theta)^2 = ((u - cx)/fx)^2 + ((v - cy)/fy)^2.
            const double tx = (u - cam.cx) / cam.fx, ty = (v - cam.cy) / cam.fy;
            const double r2 = tx * tx + ty * ty, cos_theta = std::cos(std::atan(std::sqrt(r2)));
            double expected = 1.0 + vig.k1 * r2 + vig.k2 * r2 * r2 + vig.k3 * r2 * r2 * r2;
            if (vig.natural) expected *= std::pow(cos_theta, 4);
            smallest = std::min(smallest, expected);
            for (int c = 0; c < 3; ++c) {
                const double on_axis = field.at(u, v, c) * stage.electrons_per_radiance(c, 10.0);
                const double got = (out.linear_dn.at(u, v, c) - black) / (K * on_axis);
                ASSERT_NEAR(got / expected, 1.0, tol) << u << ", " << v << ", " << c;
            }
        }
    if (vig.natural) {
        EXPECT_LT(smallest, 0.55);  // the corners are well into the falloff
    }
}

TEST(Vignetting, NaturalCos4) { check_falloff({}, 1e-3); }

TEST(Vignetting, Cos4TimesThePolynomial) {
    Vignetting v;
    v.k1 = -0.2;
    v.k2 = 0.08;
    v.k3 = -0.02;
    check_falloff(v, 1e-3);
}

TEST(Vignetting, PolynomialAlone) {
    Vignetting v;
    v.natural = false;
    v.k1 = -0.3;
    check_falloff(v, 1e-3);
}

TEST(Vignetting, FactorAtTheCornerOfTheAuthorsView) {
    // 67 degrees across: the edge of the view at 33.5 degrees keeps cos^4 = 0.48.
    const double t = std::tan(33.5 * M_PI / 180.0);
    EXPECT_NEAR(cos4_from_r2(t * t), 0.48, 0.005);
}

}  // namespace
}  // namespace deepsea
