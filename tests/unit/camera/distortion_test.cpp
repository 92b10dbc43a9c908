// Lens distortion against OpenCV's documented model (cv::projectPoints; the formula is written
// out again here from OpenCV's calib3d documentation, not taken from the library), and the
// refusal of a distortion that folds the image over.
#include <gtest/gtest.h>

#include <cmath>

#include "camera_test_util.h"
#include "deepsea/core/random.h"
#include "deepsea/optics/schema.h"

namespace deepsea {
namespace {

using namespace camera_test;

/// OpenCV's documentation: x'' = x' (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x' y' + p2 (r^2 +
/// 2 x'^2), y'' = y' (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y'^2) + 2 p2 x' y',
/// u = fx x'' + cx, v = fy y'' + cy, for the point (X, Y, Z) = (x', y', 1).
void opencv_project(const Camera& cam, double k1, double k2, double p1, double p2, double k3,
                    double x, double y, double& u, double& v) {
    const double r2 = std::pow(x, 2) + std::pow(y, 2);
    const double radial = 1 + k1 * r2 + k2 * std::pow(r2, 2) + k3 * std::pow(r2, 3);
    const double xpp = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * std::pow(x, 2));
    const double ypp = y * radial + p1 * (r2 + 2 * std::pow(y, 2)) + 2 * p2 * x * y;
    u = cam.fx * xpp + cam.cx;
    v = cam.fy * ypp + cam.cy;
}

struct Lens5 {
    double k1, k2, p1, p2, k3;
};

// A typical calibration of a wide action camera (barrel) and a mild pincushion with
// decentring: OpenCV calibrations of the kind users bring.
const Lens5 kLenses[] = {{-0.28, 0.09, 0.0012, -0.0008, -0.012}, {0.08, -0.02, -0.002, 0.003, 0.0}};

TEST(Distortion, ForwardModelIsOpenCvs) {
    const Camera cam{640, 480, 500.0, 505.0, 321.7, 238.2};
    Rng rng(3);
    for (const Lens5& l : kLenses) {
        const Distortion d{l.k1, l.k2, l.p1, l.p2, l.k3};
        for (int i = 0; i < 100; ++i) {
            const double x = (rng.uniform() - 0.5) * 1.3, y = (rng.uniform() - 0.5) * 1.0;
            double u, v, xd, yd;
            opencv_project(cam, l.k1, l.k2, l.p1, l.p2, l.k3, x, y, u, v);
            distort(d, x, y, xd, yd);
            EXPECT_NEAR(cam.fx * xd + cam.cx, u, 1e-9);
            EXPECT_NEAR(cam.fy * yd + cam.cy, v, 1e-9);
            // And the inverse lands back on the ray.
            double ux, uy;
            ASSERT_TRUE(undistort(d, cam.ray_x(u), cam.ray_y(v), ux, uy));
            EXPECT_NEAR(cam.fx * ux, cam.fx * x, 1e-6);
            EXPECT_NEAR(cam.fy * uy, cam.fy * y, 1e-6);
        }
    }
}

TEST(Distortion, ResampledPixelsLandWhereOpenCvProjectsThem) {
    // The rendered (pinhole) image holds its own pixel coordinates: R = u + 1, G = v + 1.
    // The stage records each pixel from where the lens sends it; the position read back from
    // the recorded image, projected by OpenCV's formula, must be that pixel, to 1e-3 px.
    const Camera cam{320, 240, 260.0, 262.0, 161.4, 118.9};
    for (const Lens5& l : kLenses) {
        CameraModel m;
        m.lens.distortion = {l.k1, l.k2, l.p1, l.p2, l.k3};
        m.lens.vignetting.natural = false;
        m.sensor.noise = false;
        m.sensor.dark_current = 0.0;
        m.sensor.full_well = 1e9;
        m.sensor.bits = 16;
        m.sensor.system_gain = 1.0;
        const CameraStage stage(m, cam);
        const double scale = 100.0 / stage.electrons_per_radiance(0, 10.0);  // 100 e- per px
        Image ramp(cam.width, cam.height, 3);
        for (int v = 0; v < cam.height; ++v)
            for (int u = 0; u < cam.width; ++u) {
                ramp.at(u, v, 0) = float(scale * (u + 1));
                ramp.at(u, v, 1) = float(scale * (v + 1) * stage.electrons_per_radiance(0, 10.0) /
                                         stage.electrons_per_radiance(1, 10.0));
                ramp.at(u, v, 2) = 0.0f;
            }
        CameraOutput out;
        CameraLayerSet set;
        set.linear_dn = true;
        stage.apply(out, ramp, 0, set);
        const double black = black_level(m.sensor);
        Rng rng(11);
        int checked = 0;
        while (checked < 100) {
            const int u = int(rng.uniform() * cam.width), v = int(rng.uniform() * cam.height);
            const double su = (out.linear_dn.at(u, v, 0) - black) / 100.0 - 1.0;
            const double sv = (out.linear_dn.at(u, v, 1) - black) / 100.0 - 1.0;
            // Beyond the rendered image its edge repeats: positions read back within 0.01 px of
            // the edge are that repeat (float linear DN carry about 1e-4 px: 25024 DN at the
            // last row can read 25023.998, 238.99998 px, below the edge's 239).
            constexpr double kEdge = 0.01;
            if (su <= kEdge || sv <= kEdge || su >= cam.width - 1 - kEdge ||
                sv >= cam.height - 1 - kEdge)
                continue;
            double pu, pv;
            opencv_project(cam, l.k1, l.k2, l.p1, l.p2, l.k3, cam.ray_x(su), cam.ray_y(sv), pu, pv);
            EXPECT_NEAR(pu, u, 1e-3) << "pixel " << u << ", " << v;
            EXPECT_NEAR(pv, v, 1e-3) << "pixel " << u << ", " << v;
            ++checked;
        }
    }
}

TEST(Distortion, BarrelLooksBeyondThePinholeImage) {
    const Camera cam{320, 240, 260.0, 260.0, 159.5, 119.5};
    const DistortionMap barrel(cam, {-0.28, 0.09, 0.0, 0.0, 0.0});
    EXPECT_GT(barrel.outside_fraction(), 0.01);
    double su, sv;
    barrel.source(0, 0, su, sv);  // the corner sees farther out than the pinhole's corner
    EXPECT_LT(su, 0.0);
    EXPECT_LT(sv, 0.0);
    const DistortionMap pincushion(cam, {0.08, 0.0, 0.0, 0.0, 0.0});
    EXPECT_EQ(pincushion.outside_fraction(), 0.0);
    EXPECT_TRUE(DistortionMap(cam, {}).empty());
}

std::string refusal(const Distortion& d, const Camera& cam) {
    try {
        CameraModel m;
        m.lens.distortion = d;
        CameraStage stage(m, cam);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(Distortion, FoldingIsRefusedNamingTheKey) {
    const Camera cam{400, 400, 200.0, 200.0, 199.5, 199.5};  // corners at r = 1.41
    // r (1 - 0.5 r^2) turns back at r = 0.816, inside the field.
    const std::string radial = refusal({-0.5, 0.0, 0.0, 0.0, 0.0}, cam);
    EXPECT_EQ(radial.rfind("camera.lens.distortion: folds the image over: the radial mapping", 0),
              0u)
        << radial;
    EXPECT_NE(radial.find("r = 0.816"), std::string::npos) << radial;
    EXPECT_EQ(radial.find('\n'), std::string::npos);
    // A narrow dip of the slope (k2 against k3) inside the field.
    EXPECT_NE(refusal({0.0, -1.2, 0.0, 0.0, 0.8}, cam).find("stops increasing"), std::string::npos);
    // Tangential terms strong enough to fold.
    const std::string tangential = refusal({0.0, 0.0, 0.9, 0.0, 0.0}, cam);
    EXPECT_EQ(tangential.rfind("camera.lens.distortion: folds the image over", 0), 0u)
        << tangential;
    // A strong but monotone barrel over this field is accepted.
    EXPECT_EQ(refusal({-0.12, 0.01, 0.0, 0.0, 0.0}, cam), "");
}

}  // namespace
}  // namespace deepsea
