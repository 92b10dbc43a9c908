// Baking through a port (docs/port-bake.md, "Baking through a port"): an asset baked along the
// water-side rays, rendered through the same port, against exact integration along the
// refracted rays; a centred dome's lattice against no port's; a port that differs refused.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/runtime/renderer.h"
#include "port_fixtures.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

const Camera kCam = testing::small_camera();

Asset baked(const std::optional<Port>& port, int step = 4, double z_max = 0) {
    BakeSettings s;
    s.step = step;
    s.z_max = z_max;  // 0: auto (searched along the columns' own rays)
    s.port = port;
    return bake(kCam, testing::two_lamps(), testing::ib_with_forward(), s);
}

Layers rendered(const Asset& asset, const std::optional<Port>& port, const Image& depth) {
    RenderSettings rs;
    rs.port = port;
    Renderer r(asset, rs);
    Frame f{testing::plane_scene(kCam).rgb, depth};
    Layers out;
    r.render(out, f);
    return out;
}

}  // namespace

TEST(PortBake, RenderedBackscatterAgainstExactIntegrationAlongTheRefractedRays) {
    // Each asset baked through its port and rendered through it (the pinhole lookup on the
    // water-side columns), against the exact integral from the port's outer surface along each
    // pixel's own refracted ray (traced here) to a plane at planar depth 2.5 m: the bake's bar.
    const std::optional<Port> ports[] = {std::nullopt,
                                         test::dome_port({0, 0, 0}, 0.05, 0.01),
                                         test::flat_port({0, 0, 1}, 0.03, 0.012),
                                         test::flat_port({0, 0, 1}, 0.1, 0.02),
                                         test::dome_port({0.01, -0.008, 0.005}, 0.05, 0.01),
                                         test::flat_port({0.1, 0.05, 1}, 0.05, 0.015)};
    const char* names[] = {"no port",    "centred dome 5 cm",     "flat 3 cm",
                           "flat 10 cm", "dome decentred 1.4 cm", "flat tilted 6 deg, 5 cm"};
    const Image depth(kCam.width, kCam.height, 1, 2.5f);
    Quadrature q;
    q.rel_tol = 1e-6;  // 4 orders below the 0.25 % bar: the exact side's error is immaterial
    for (int p = 0; p < 6; ++p) {
        const Asset asset = baked(ports[p]);
        ASSERT_EQ(asset.info.port.has_value(), ports[p].has_value());
        const Layers out = rendered(asset, ports[p], depth);
        double sum = 0, max = 0;
        long n = 0;
        for (int v = 1; v < kCam.height; v += 3) {
            for (int u = 1; u < kCam.width; u += 3) {
                if (ports[p] && out.mask.at(u, v) != 1.0f) continue;
                Vec3 o{0, 0, 0}, w = normalize(kCam.ray(u, v));
                if (ports[p]) {
                    const PortRay ray = trace_port(*ports[p], kCam, u, v);
                    o = ray.origin;
                    w = ray.direction[1];
                }
                const double t = (2.5 - o.z) / w.z;
                const Rgb exact =
                    backscatter_integral(asset.info.rig, asset.info.water, o, w, 0, t, q).value;
                double e = 0;
                for (int c = 0; c < 3; ++c)
                    e = std::max(e, std::fabs(out.backscatter.at(u, v, c) - exact[c]) / exact[c]);
                sum += e;
                max = std::max(max, e);
                ++n;
            }
        }
        std::printf(
            "%s: baked through it, rendered backscatter vs exact along the refracted rays: mean "
            "%.3f %%, max %.3f %% (%ld pixels); the bake's check: mean %.3f %%, max %.3f %%\n",
            names[p], 100 * sum / n, 100 * max, n, 100 * asset.info.check.mean_rel,
            100 * asset.info.check.max_rel);
        EXPECT_GT(n, 900);
        EXPECT_LT(sum / n, 0.0025) << names[p];
        EXPECT_LT(max, 0.01) << names[p];
        EXPECT_TRUE(asset.info.check.done);
        EXPECT_LT(asset.info.check.mean_rel, 0.0025) << names[p];
        EXPECT_LT(asset.info.check.max_rel, 0.01) << names[p];
    }
}

TEST(PortBake, DispersionsErrorAgainstEachChannelsOwnRay) {
    // The columns follow the green channel's ray; with a dispersive n_water red and blue leave
    // the port at slightly other angles. Their error against the exact integral along each
    // channel's own refracted ray, to a plane at 2.5 m, flat port 3 cm.
    Port port = test::flat_port({0, 0, 1}, 0.03, 0.012);
    port.n_water = {1.339, 1.342, 1.347};
    const Asset asset = baked(port);
    const Layers out = rendered(asset, port, Image(kCam.width, kCam.height, 1, 2.5f));
    double sum[3] = {0, 0, 0}, max[3] = {0, 0, 0};
    long n = 0;
    for (int v = 1; v < kCam.height; v += 3) {
        for (int u = 1; u < kCam.width; u += 3) {
            const PortRay ray = trace_port(port, kCam, u, v);
            for (int c = 0; c < 3; ++c) {
                const Vec3& w = ray.direction[c];
                const double exact =
                    backscatter_integral(asset.info.rig, asset.info.water, ray.origin, w, 0,
                                         (2.5 - ray.origin.z) / w.z, {1e-6})
                        .value[c];
                const double e = std::fabs(out.backscatter.at(u, v, c) - exact) / exact;
                sum[c] += e;
                max[c] = std::max(max[c], e);
            }
            ++n;
        }
    }
    std::printf(
        "dispersive flat port, each channel against its own ray: mean R %.3f %%, G %.3f "
        "%%, B %.3f %%; max R %.3f %%, G %.3f %%, B %.3f %%\n",
        100 * sum[0] / n, 100 * sum[1] / n, 100 * sum[2] / n, 100 * max[0], 100 * max[1],
        100 * max[2]);
    for (int c = 0; c < 3; ++c) {
        EXPECT_LT(sum[c] / n, 0.0025) << c;
        EXPECT_LT(max[c], 0.01) << c;
    }
}

TEST(PortBake, CentredDomeBakesTheLatticeWithoutAPortLessTheDisplacedWater) {
    // Camera at the dome's centre: each water-side ray is the pinhole ray from s0 = R + T on,
    // so B_port(z) = exp(c s0) [B_pinhole(z) - B(0 .. s0)] at every lattice sample.
    const double R = 0.05, T = 0.01, s0 = R + T;
    const Asset pin = baked(std::nullopt, 8, 10.0);
    const Asset port = baked(test::dome_port({0, 0, 0}, R, T), 8, 10.0);
    const Lattice& l = pin.lattice();
    ASSERT_EQ(l.ni, port.lattice().ni);
    ASSERT_EQ(l.z, port.lattice().z);
    double worst = 0;
    for (int i = 0; i < l.ni; ++i) {
        for (int j = 0; j < l.nj; ++j) {
            const Vec3 w = normalize(kCam.ray(l.u(i), l.v(j)));
            const Rgb head =
                backscatter_integral(pin.info.rig, pin.info.water, w, 0, s0, {1e-10}).value;
            const Rgb total = pin.at(i, j, l.slabs());
            for (int k = 0; k < l.nk(); ++k) {
                const bool inside = l.z[k] * length(kCam.ray(l.u(i), l.v(j))) <= s0;
                for (int c = 0; c < 3; ++c) {
                    const double want = inside ? 0.0
                                               : std::exp(pin.info.water.c[c] * s0) *
                                                     (pin.at(i, j, k)[c] - head[c]);
                    worst = std::max(worst, std::fabs(port.at(i, j, k)[c] - want) / total[c]);
                }
            }
        }
    }
    std::printf(
        "centred dome vs no port less the displaced water: worst %.2e of a column's total\n",
        worst);
    EXPECT_LT(worst, 2e-5);
}

TEST(PortBake, PortThatDiffersFromTheAssetsIsRefusedInOneLine) {
    const Port flat = test::flat_port({0, 0, 1}, 0.03, 0.012);
    const Asset asset = baked(flat, 16);
    const auto refused = [&](const std::optional<Port>& port, const char* frames_side) {
        RenderSettings rs;
        rs.port = port;
        try {
            Renderer r(asset, rs);
            ADD_FAILURE() << "accepted " << frames_side;
        } catch (const AssetError& e) {
            const std::string m = e.what();
            EXPECT_NE(m.find("baked through a flat port (normal [0, 0, 1], distance 0.03 m"),
                      std::string::npos)
                << m;
            EXPECT_NE(m.find(frames_side), std::string::npos) << m;
            EXPECT_EQ(m.find('\n'), std::string::npos) << m;
        }
    };
    refused(std::nullopt, "the frames' camera has no port");
    refused(test::flat_port({0, 0, 1}, 0.04, 0.012),
            "looks through a flat port (normal [0, 0, 1], "
            "distance 0.04 m");
    refused(test::dome_port({0, 0, 0}, 0.05, 0.01), "looks through a dome port");
    // The same port is accepted; Fresnel changes only the camera stage, not a ray.
    Port fresnel = flat;
    fresnel.fresnel = true;
    RenderSettings rs;
    rs.port = fresnel;
    EXPECT_NO_THROW(Renderer(asset, rs));
    // A pinhole asset renders through any port (the approximate lookup, port_backscatter.h).
    const Asset pin = baked(std::nullopt, 16);
    rs.port = flat;
    EXPECT_NO_THROW(Renderer(pin, rs));
}

}  // namespace deepsea
