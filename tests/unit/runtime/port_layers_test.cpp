// Rendering through a port, the layers (docs/ports.md, "Rendering through a port"): a dome with
// the camera at its centre against no port, the mask where rays leave the input's view, the
// backscatter's error against exact integration along the refracted rays, refused ports.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/runtime/port_rays.h"
#include "deepsea/runtime/renderer.h"
#include "port_fixtures.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

struct PortSetup {
    Camera cam = testing::small_camera();
    Rig rig = testing::two_lamps();
    Water water = testing::ib_with_forward();
    Asset asset;
    testing::PlaneScene scene = testing::plane_scene(cam);
    PortSetup() {
        BakeSettings s;
        s.step = 4;
        asset = bake(cam, rig, water, s);
    }
    Layers render(const std::optional<Port>& port) const {
        RenderSettings rs;
        rs.port = port;
        Renderer r(asset, rs);
        Frame f{scene.rgb, scene.depth};
        Layers out;
        r.render(out, f);
        return out;
    }
};

const PortSetup& setup() {
    static const PortSetup s;
    return s;
}

/// A dome of `radius` and `glass` thickness, centred on the camera unless `centre` says.
Port dome(double radius, double glass, Vec3 centre = {0, 0, 0}) {
    return test::dome_port(centre, radius, glass);
}

using test::flat_port;

/// Largest |a - b| over a layer relative to the layer's largest |b|.
double worst(const Image& a, const Image& b) {
    double diff = 0, top = 0;
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        diff = std::max(diff, double(std::fabs(a.data[i] - b.data[i])));
        top = std::max(top, double(std::fabs(b.data[i])));
    }
    return top > 0 ? diff / top : diff;
}

}  // namespace

TEST(PortLayers, DomeWithTheCameraAtItsCentreRendersAsWithoutAPort) {
    const PortSetup& s = setup();
    const Layers none = s.render(std::nullopt);
    // A vanishing dome: the same rays from (almost) the same point.
    const Layers tiny = s.render(dome(1e-6, 1e-6));
    ASSERT_FALSE(tiny.mask.empty());
    EXPECT_TRUE(none.mask.empty());
    for (float m : tiny.mask.data) EXPECT_EQ(m, 1.0f);
    const Image Layers::*layers[] = {&Layers::final,       &Layers::direct,       &Layers::forward,
                                     &Layers::backscatter, &Layers::transmission, &Layers::depth,
                                     &Layers::normal};
    for (auto layer : layers) EXPECT_LT(worst(tiny.*layer, none.*layer), 2e-5);

    // A real one (5 cm, 1 cm acrylic): the same geometry; the light's path in water starts
    // R + T from the camera, so D and T gain exp(c (R + T)) and B loses its first R + T and
    // gains the same factor.
    const double rt = 0.06;
    const Layers real = s.render(dome(0.05, 0.01));
    EXPECT_LT(worst(real.depth, none.depth), 2e-6);
    EXPECT_LT(worst(real.normal, none.normal), 2e-5);
    Image direct = none.direct, back = none.backscatter;
    for (int v = 0; v < s.cam.height; ++v) {
        for (int u = 0; u < s.cam.width; ++u) {
            const double cos_phi = 1.0 / length(s.cam.ray(u, v));
            const Rgb b0 = s.asset.sample(u, v, rt * cos_phi);
            for (int c = 0; c < 3; ++c) {
                direct.at(u, v, c) *= float(std::exp(s.water.c[c] * rt));
                back.at(u, v, c) = float((back.at(u, v, c) - b0[c]) * std::exp(s.water.c[c] * rt));
            }
        }
    }
    EXPECT_LT(worst(real.direct, direct), 2e-5);
    EXPECT_LT(worst(real.backscatter, back), 2e-5);
}

TEST(PortLayers, MaskIsZeroWhereTheRayLeavesTheInputsView) {
    // A flat port tilted 45 degrees about y, beyond the camera's half field of view (34
    // degrees): the water-side rays crowd around its normal, and those of the right edge look
    // past the input's right edge (up to 37 degrees off the axis) at the plane 3 m away.
    const PortSetup& s = setup();
    const Port port = flat_port({1, 0, 1}, 0.02, 0.01);
    RenderSettings rs;
    rs.port = port;
    Renderer r(s.asset, rs);
    Image depth(s.cam.width, s.cam.height, 1, 3.0f);
    Frame f{s.scene.rgb, depth};
    Layers out;
    r.render(out, f);
    long outside = 0, inside = 0;
    for (int v = 0; v < s.cam.height; ++v) {
        for (int u = 0; u < s.cam.width; ++u) {
            const PortRay ray = trace_port(port, s.cam, u, v);
            const Vec3& w = ray.direction[1];
            const Vec3 X = ray.origin + w * ((3.0 - ray.origin.z) / w.z);
            const double us = s.cam.cx + s.cam.fx * X.x / X.z;
            const double vs = s.cam.cy + s.cam.fy * X.y / X.z;
            const bool in =
                us > 0.5 && us < s.cam.width - 1.5 && vs > 0.5 && vs < s.cam.height - 1.5;
            const bool out_of_view =
                us < -1.5 || us > s.cam.width + 0.5 || vs < -1.5 || vs > s.cam.height + 0.5;
            if (in) {
                ++inside;
                EXPECT_EQ(out.mask.at(u, v), 1.0f) << u << ", " << v;
                EXPECT_NEAR(out.depth.at(u, v), 3.0f, 1e-5f);
            } else if (out_of_view) {
                ++outside;
                EXPECT_EQ(out.mask.at(u, v), 0.0f) << u << ", " << v;
                EXPECT_EQ(out.depth.at(u, v), 0.0f);
                EXPECT_EQ(out.direct.at(u, v, 1), 0.0f);
                EXPECT_GT(out.backscatter.at(u, v, 1), 0.0f);  // open water
            }
        }
    }
    std::printf("%ld pixels see the plane, %ld look past the input's view\n", inside, outside);
    EXPECT_GT(inside, 1000);
    EXPECT_GT(outside, 200);
}

TEST(PortLayers, PortThatSeesNothingOfTheInputIsRefusedBeforeWork) {
    // A narrow camera behind a flat port tilted 40 degrees: every water-side ray turns about
    // 11 degrees off the axis, far outside a 3-degree view.
    const PortSetup& s = setup();
    RenderSettings rs;
    rs.camera = Camera{120, 90, 1200.0, 1200.0, 59.5, 44.5};
    rs.port = flat_port({std::sin(0.7), 0, std::cos(0.7)}, 0.02, 0.01);
    try {
        Renderer r(s.asset, rs);
        FAIL() << "accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("camera.port: no pixel's water-side ray sees"),
                  std::string::npos)
            << e.what();
    }
}

TEST(PortLayers, BackscatterAlongRefractedRaysAgainstExactIntegration) {
    // The asset is baked along pinhole rays; through a port each water-side ray is looked up
    // along the pinhole column of its direction (PortBackscatter). Its error against exact
    // integration along the refracted ray from the port, to a plane 2.5 m away.
    const PortSetup& s = setup();
    Image depth(s.cam.width, s.cam.height, 1, 2.5f);
    Frame f{s.scene.rgb, depth};
    const std::optional<Port> ports[] = {
        std::nullopt, dome(0.05, 0.01), flat_port({0, 0, 1}, 0.03, 0.012),
        flat_port({0, 0, 1}, 0.1, 0.02), dome(0.05, 0.01, {0.01, -0.008, 0.005})};
    const char* names[] = {"no port (the lattice's own error)", "centred dome 5 cm", "flat 3 cm",
                           "flat 10 cm", "dome decentred 1.4 cm"};
    // max relative error (G channel), measured: 0.022 %, 0.036 %, 0.59 %, 1.95 %, 0.74 %
    const double bars[] = {0.001, 0.001, 0.01, 0.03, 0.01};
    Quadrature q;
    q.rel_tol = 1e-7;
    for (int p = 0; p < 5; ++p) {
        RenderSettings rs;
        rs.port = ports[p];
        Renderer r(s.asset, rs);
        Layers out;
        r.render(out, f);
        double sum = 0, max = 0;
        long n = 0;
        for (int v = 1; v < s.cam.height; v += 4) {
            for (int u = 1; u < s.cam.width; u += 4) {
                if (ports[p] && out.mask.at(u, v) != 1.0f) continue;
                PortRay ray;
                ray.direction[1] = normalize(s.cam.ray(u, v));
                if (ports[p]) ray = trace_port(*ports[p], s.cam, u, v);
                const Vec3& w = ray.direction[1];
                const double t = (2.5 - ray.origin.z) / w.z;
                const Rgb exact =
                    backscatter_integral(s.rig, s.water, ray.origin, w, 0, t, q).value;
                const double e = std::fabs(out.backscatter.at(u, v, 1) - exact.g) / exact.g;
                sum += e;
                max = std::max(max, e);
                ++n;
            }
        }
        std::printf(
            "%s: backscatter vs exact along the refracted rays: mean %.3f %%, max %.3f %% "
            "(%ld pixels)\n",
            names[p], 100 * sum / n, 100 * max, n);
        EXPECT_GT(n, 500);
        EXPECT_LT(max, bars[p]) << names[p];
    }
}

}  // namespace deepsea
