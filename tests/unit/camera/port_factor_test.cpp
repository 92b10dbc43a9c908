// The port's radiance factor in the camera stage (docs/ports.md, "Radiance across the
// interfaces"; docs/camera.md): the stage's signal through a port is the signal without it
// times the n^2 law (and Fresnel's transmittance where asked), pixel by pixel.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "camera_test_util.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/optics/port.h"

namespace deepsea {
namespace {

using camera_test::pinhole;

const Camera kCam = pinhole(81, 61, 60.0);  // odd: the centre pixel is on the axis

CameraModel quiet_model() {
    CameraModel m;
    m.sensor.noise = false;  // the signal alone
    return m;
}

Port flat(bool fresnel) {
    Port p;
    p.flat.normal = {0.08, -0.05, 1.0};  // a little tilted: the factor varies over the image
    p.flat.distance = 0.03;
    p.flat.glass_thickness = 0.012;
    p.n_water = {1.339, 1.342, 1.347};
    p.fresnel = fresnel;
    return p;
}

/// A radiance that varies over the image, low enough that no pixel reaches the full well.
Image radiance() {
    Image img(kCam.width, kCam.height, 3);
    for (int v = 0; v < kCam.height; ++v)
        for (int u = 0; u < kCam.width; ++u)
            for (int c = 0; c < 3; ++c)
                img.at(u, v, c) = float(0.002 * (1.0 + 0.5 * std::sin(0.3 * u + 0.2 * v + c)));
    return img;
}

/// linear DN above the black level of one frame.
Image signal(const CameraStage& stage, const Image& rad) {
    CameraOutput out, dark;
    CameraLayerSet layers;
    layers.linear_dn = true;
    stage.apply(out, rad, 1, layers);
    stage.apply(dark, Image(kCam.width, kCam.height, 3, 0.0f), 1, layers);
    for (std::size_t i = 0; i < out.linear_dn.data.size(); ++i)
        out.linear_dn.data[i] -= dark.linear_dn.data[i];
    return out.linear_dn;
}

}  // namespace

TEST(PortFactor, StageThroughAPortIsTheStageWithoutTimesTheFactorMap) {
    const Image rad = radiance();
    const CameraStage plain(quiet_model(), kCam);
    const Port port = flat(false);
    const CameraStage through(quiet_model(), kCam, port);
    const Image a = signal(plain, rad), b = signal(through, rad);
    double worst = 0;
    for (int v = 0; v < kCam.height; ++v) {
        for (int u = 0; u < kCam.width; ++u) {
            const Rgb f = port_radiance_factor(port, trace_port(port, kCam, u, v));
            for (int c = 0; c < 3; ++c) {
                ASSERT_GT(a.at(u, v, c), 0.0f);
                worst = std::max(worst, std::fabs(b.at(u, v, c) / (f[c] * a.at(u, v, c)) - 1.0));
                EXPECT_EQ(through.port_factor(u, v, c), float(f[c]));
                EXPECT_EQ(plain.port_factor(u, v, c), 1.0f);
            }
        }
    }
    EXPECT_LT(worst, 1e-5);
    // On the axis of a flat port the n^2 law alone: (n_air / n_water)^2, 0.555 in green.
    const int uc = kCam.width / 2, vc = kCam.height / 2;
    const Port axial = [] {
        Port p = flat(false);
        p.flat.normal = {0, 0, 1};
        return p;
    }();
    const CameraStage centred(quiet_model(), kCam, axial);
    for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(centred.port_factor(uc, vc, c), 1.0 / (axial.n_water[c] * axial.n_water[c]),
                    1e-7);
}

TEST(PortFactor, FresnelOnOverOffIsTheTransmittanceOfBothSurfaces) {
    const Image rad = radiance();
    const Port off = flat(false), on = flat(true);
    const Image a = signal(CameraStage(quiet_model(), kCam, off), rad);
    const Image b = signal(CameraStage(quiet_model(), kCam, on), rad);
    double worst = 0;
    for (int v = 0; v < kCam.height; v += 3) {
        for (int u = 0; u < kCam.width; u += 3) {
            // Each polarisation carried through both surfaces, from the ray's cosines.
            const PortRay r = trace_port(on, kCam, u, v);
            const auto t1 =
                fresnel_transmittance(on.n_air, on.n_glass, r.cos_air, r.cos_glass_inner);
            for (int c = 0; c < 3; ++c) {
                const auto t2 = fresnel_transmittance(on.n_glass, on.n_water[c], r.cos_glass_outer,
                                                      r.cos_water[c]);
                const double T = 0.5 * (t1.s * t2.s + t1.p * t2.p);
                EXPECT_LT(T, 1.0);
                worst = std::max(worst, std::fabs(b.at(u, v, c) / (T * a.at(u, v, c)) - 1.0));
            }
        }
    }
    EXPECT_LT(worst, 1e-5);
    // At normal incidence the closed form: (1 - r1^2)(1 - r2^2), r = (n1 - n2) / (n1 + n2).
    Port axial = on;
    axial.flat.normal = {0, 0, 1};
    const CameraStage with(quiet_model(), kCam, axial);
    const int uc = kCam.width / 2, vc = kCam.height / 2;
    const double r1 = (1.0 - 1.49) / (1.0 + 1.49), r2 = (1.49 - 1.342) / (1.49 + 1.342);
    EXPECT_NEAR(with.port_factor(uc, vc, 1), (1 - r1 * r1) * (1 - r2 * r2) / (1.342 * 1.342), 1e-7);
}

}  // namespace deepsea
