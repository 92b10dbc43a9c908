// The exact reference through a port (docs/port-bake.md, "The exact reference through a port"):
// against the runtime's render of the same frame through the same port, an asset baked through
// it; and a dome centred on the camera against no port, up to the radiance factor.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "deepsea/bake/bake.h"
#include "deepsea/reference/reference.h"
#include "deepsea/runtime/renderer.h"
#include "port_fixtures.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

const Camera kCam = testing::small_camera();

/// Relative error of a against b, with a floor of `floor` times the layer's largest |b|.
double rel(float a, float b, double top, double floor = 1e-3) {
    return std::fabs(double(a) - b) / std::max(std::fabs(double(b)), floor * top);
}

double top_of(const Image& img) {
    double t = 0;
    for (const float x : img.data) t = std::max(t, double(std::fabs(x)));
    return t;
}

}  // namespace

TEST(PortReference, AgainstTheRuntimeThroughFlatAndDomePorts) {
    // The plane scene (a tilted plane, a nearer box with a depth step, a patch of open water),
    // each port baked into its asset, rendered by the runtime (float march) and by the reference
    // (find_port_hit in double, every backscatter integrated along the refracted ray).
    const Port ports[] = {test::flat_port({0, 0, 1}, 0.03, 0.012),
                          test::flat_port({0.1, 0.05, 1}, 0.05, 0.015),
                          test::dome_port({0.01, -0.008, 0.005}, 0.05, 0.01)};
    const char* names[] = {"flat 3 cm", "flat tilted 6 deg, 5 cm", "dome decentred 1.4 cm"};
    const testing::PlaneScene scene = testing::plane_scene(kCam);
    const Rig rig = testing::two_lamps();
    const Water water = testing::ib_with_forward();
    for (int p = 0; p < 3; ++p) {
        BakeSettings s;
        s.step = 4;
        s.port = ports[p];
        const Asset asset = bake(kCam, rig, water, s);
        RenderSettings rs;
        rs.port = ports[p];
        Renderer renderer(asset, rs);
        Layers rt;
        Frame frame{scene.rgb, scene.depth};
        renderer.render(rt, frame);
        ReferenceOptions opt;
        opt.port = ports[p];
        opt.open_water_z = asset.lattice().z_max();  // open water ends where the asset does
        opt.quadrature.rel_tol = 1e-6;
        const Layers ref = render_reference(kCam, rig, water, scene.rgb, scene.depth, opt);
        ASSERT_EQ(ref.mask.width, kCam.width);

        long n = 0, mask_diff = 0, kind_diff = 0, surfaces = 0;
        double bs_sum = 0, bs_max = 0, direct_max = 0, depth_max = 0, fin_sum = 0;
        const double top_direct = top_of(ref.direct), top_final = top_of(ref.final);
        for (int v = 0; v < kCam.height; ++v) {
            for (int u = 0; u < kCam.width; ++u) {
                ++n;
                if (rt.mask.at(u, v) != ref.mask.at(u, v)) ++mask_diff;
                const float zr = ref.depth.at(u, v), zt = rt.depth.at(u, v);
                if ((zr > 0) != (zt > 0)) ++kind_diff;
                double e = 0;
                for (int c = 0; c < 3; ++c)
                    e = std::max(
                        e, rel(rt.backscatter.at(u, v, c), ref.backscatter.at(u, v, c), 1.0, 0.0));
                bs_sum += e;
                bs_max = std::max(bs_max, e);
                for (int c = 0; c < 3; ++c)
                    fin_sum += rel(rt.final.at(u, v, c), ref.final.at(u, v, c), top_final) / 3;
                // the surface's own values away from the depth map's edges, where a hit a float
                // rounding away can take the other side
                if (!(zr > 0 && zt > 0) || testing::near_edge(ref.depth, u, v)) continue;
                ++surfaces;
                depth_max = std::max(depth_max, std::fabs(double(zt) - zr) / zr);
                for (int c = 0; c < 3; ++c)
                    direct_max = std::max(
                        direct_max, rel(rt.direct.at(u, v, c), ref.direct.at(u, v, c), top_direct));
            }
        }
        std::printf(
            "%s: runtime vs reference through the port: backscatter mean %.3f %% max %.3f %%, "
            "direct max %.2e, depth max %.2e (%ld surface pixels), final mean %.3f %%; mask "
            "differs at %ld, surface/none at %ld of %ld pixels\n",
            names[p], 100 * bs_sum / n, 100 * bs_max, direct_max, depth_max, surfaces,
            100 * fin_sum / n, mask_diff, kind_diff, n);
        EXPECT_GT(surfaces, n / 2) << names[p];
        EXPECT_LE(mask_diff, n / 200) << names[p];
        EXPECT_LE(kind_diff, n / 200) << names[p];
        EXPECT_LT(depth_max, 1e-4) << names[p];
        EXPECT_LT(direct_max, 1e-3) << names[p];
        // the baked lookup's bar (0.25 % mean, 1 % max)
        EXPECT_LT(bs_sum / n, 0.0025) << names[p];
        EXPECT_LT(bs_max, 0.01) << names[p];
        EXPECT_LT(fin_sum / n, 0.01) << names[p];
    }
}

TEST(PortReference, DomeCentredOnTheCameraEqualsNoPortUpToTheRadianceFactor) {
    // A vanishing dome (1 micrometre) on the camera centre: the water-side layers equal the
    // reference without a port to rounding, and what reaches the camera is the n^2 law times the
    // Fresnel transmittance at normal incidence, computed here from the indices.
    const testing::PlaneScene scene = testing::plane_scene(kCam);
    const Rig rig = testing::two_lamps();
    const Water water = testing::ib_with_forward();
    Port dome = test::dome_port({0, 0, 0}, 1e-6, 1e-6);
    dome.fresnel = true;
    ReferenceOptions opt;
    opt.open_water_z = 8.0;
    opt.quadrature.rel_tol = 1e-6;  // the same for both: their difference is the port's
    const Layers none = render_reference(kCam, rig, water, scene.rgb, scene.depth, opt);
    opt.port = dome;
    const Layers through = render_reference(kCam, rig, water, scene.rgb, scene.depth, opt);
    const std::pair<const Image*, const Image*> layers[] = {
        {&through.direct, &none.direct},
        {&through.forward, &none.forward},
        {&through.backscatter, &none.backscatter},
        {&through.transmission, &none.transmission},
        {&through.depth, &none.depth},
        {&through.normal, &none.normal}};
    double layers_worst = 0;
    for (const auto& [a, b] : layers) {
        const double top = top_of(*b);
        double worst = 0;
        for (std::size_t i = 0; i < a->data.size(); ++i)
            worst = std::max(worst, std::fabs(double(a->data[i]) - b->data[i]) / top);
        EXPECT_LT(worst, 2e-5);
        layers_worst = std::max(layers_worst, worst);
    }
    for (const float m : through.mask.data) EXPECT_EQ(m, 1.0f);

    const auto fresnel = [](double n1, double n2) {
        const double r = (n1 - n2) / (n1 + n2);
        return 1 - r * r;
    };
    const double na = dome.n_air, ng = dome.n_glass, nw = dome.n_water.g;
    const double factor = (na / nw) * (na / nw) * fresnel(na, ng) * fresnel(ng, nw);
    const Image at_camera = radiance_at_camera(through.final, dome, kCam);
    const double top = top_of(none.final);
    double worst = 0;
    for (std::size_t i = 0; i < at_camera.data.size(); ++i)
        worst = std::max(worst, std::fabs(at_camera.data[i] - factor * none.final.data[i]) / top);
    std::printf(
        "centred dome: layers vs no port: worst %.2e; radiance at the camera vs no port x %.6f: "
        "worst %.2e\n",
        layers_worst, factor, worst);
    EXPECT_LT(worst, 2e-5);
}

}  // namespace deepsea
