// Rendering through a port (docs/ports.md, "Rendering through a port"): the hits of the water-side
// rays against an independent trace onto analytic scenes, a centred dome against no port, the
// flat port's field of view, the mask, refused ports.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <vector>

#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/runtime/port_rays.h"
#include "deepsea/runtime/renderer.h"
#include "port_fixtures.h"
#include "port_warp.h"
#include "runtime_fixtures.h"

namespace deepsea {

namespace {

Camera test_camera() { return Camera{240, 180, 180.0, 180.0, 119.5, 89.5}; }

using test::dome_port;
using test::flat_port;

/// An analytic scene: the first hit of a ray (origin, unit direction) at path length t > 0
/// (inf: none).
using Scene = std::function<double(const Vec3&, const Vec3&)>;

Scene plane(Vec3 n, double d) {  // n . x = d
    return [n = normalize(n), d](const Vec3& o, const Vec3& w) {
        const double t = (d - dot(n, o)) / dot(n, w);
        return t > 0 ? t : std::numeric_limits<double>::infinity();
    };
}

Scene sphere(Vec3 c, double r) {
    return [c, r](const Vec3& o, const Vec3& w) {
        const Vec3 q = o - c;
        const double b = dot(q, w), h = b * b - (dot(q, q) - r * r);
        if (h < 0) return std::numeric_limits<double>::infinity();
        const double t = -b - std::sqrt(h);
        return t > 0 ? t : std::numeric_limits<double>::infinity();
    };
}

/// The scene's planar depth as the pinhole camera sees it (open water 0).
Image depth_of(const Camera& cam, const Scene& scene) {
    Image z(cam.width, cam.height, 1);
    for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) {
            const Vec3 r = cam.ray(u, v);
            const double t = scene(Vec3(0, 0, 0), normalize(r));
            z.at(u, v) = std::isfinite(t) ? float(t * normalize(r).z) : 0.0f;
        }
    return z;
}

/// Views more grazing than this (the cosine between the surface's normal and the pinhole ray;
/// 45 degrees) are left out: there the depth map's own sampling (a chord's depth error h^2 z'' / 8
/// between pixels h apart) exceeds the bar, 4e-4 relative near the sphere's rim, whatever the
/// march.
constexpr double kMinFacing = 0.7;

struct HitErrors {
    double px = 0, rel_z = 0;
    long checked = 0, surface = 0;
};

/// Every pixel's hit against the independent trace: trace_port (double), the ray's analytic
/// intersection, its pinhole projection. Pixels whose true hit lies within `margin` px of the
/// scene's silhouette (the depth map's samples span the rim there) or of the image's border
/// are left out.
HitErrors compare_hits(const Camera& cam, const Port& port, const Scene& scene, double margin) {
    const PortRays rays(port, cam);
    const Image depth = inverse_depth(depth_of(cam, scene));
    const double z_near = nearest_surface(depth_of(cam, scene));
    HitErrors e;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const PortRay r = trace_port(port, cam, u, v);
            const Vec3& w = r.direction[1];
            const double t = scene(r.origin, w);
            if (!std::isfinite(t)) continue;
            const Vec3 X = r.origin + w * t;
            const double us = cam.cx + cam.fx * X.x / X.z, vs = cam.cy + cam.fy * X.y / X.z;
            if (us < margin || vs < margin || us > cam.width - 1 - margin ||
                vs > cam.height - 1 - margin)
                continue;
            // the surface's slope as the pinhole sees it: grazing views are left out (the
            // depth map's samples cannot describe a surface seen edge-on)
            const double eps = 1e-6;
            const Vec3 rx = normalize(cam.ray(us + eps * cam.fx, vs)),
                       ry = normalize(cam.ray(us, vs + eps * cam.fy));
            const Vec3 A = rx * scene(Vec3(0, 0, 0), rx), B = ry * scene(Vec3(0, 0, 0), ry);
            const Vec3 nrm = normalize(cross(A - X, B - X));
            if (std::fabs(dot(nrm, normalize(X))) < kMinFacing) continue;
            bool rim = false;  // a pixel near the hit sees another surface (or none)
            for (int dv = -3; dv <= 3 && !rim; ++dv)
                for (int du = -3; du <= 3 && !rim; ++du) {
                    const double pu = us + du * margin / 3, pv = vs + dv * margin / 3;
                    const Vec3 ray = normalize(cam.ray(pu, pv));
                    const double tt = scene(Vec3(0, 0, 0), ray);
                    rim = !std::isfinite(tt) || std::fabs(tt * ray.z - X.z) > 0.05 * X.z;
                }
            if (rim) continue;
            ++e.checked;
            const PortHit h = rays.hit(u, v, depth, z_near);
            if (h.kind != PortHitKind::Surface) {
                ADD_FAILURE() << "pixel " << u << ", " << v << " missed the surface";
                continue;
            }
            ++e.surface;
            e.px = std::max(e.px, std::hypot(h.u - us, h.v - vs));
            const double rz = std::fabs(h.z - X.z) / X.z;
            if (rz > e.rel_z && std::getenv("PORT_DEBUG"))
                std::printf("  worst so far: output %d %d input %.2f %.2f z %.4f true %.4f\n", u, v,
                            us, vs, h.z, X.z);
            e.rel_z = std::max(e.rel_z, rz);
        }
    }
    return e;
}

}  // namespace

TEST(PortRender, HitsMatchAnIndependentTraceOntoAnalyticScenes) {
    const Camera cam = test_camera();
    const Port ports[] = {flat_port({0, 0, 1}, 0.03, 0.012),
                          flat_port({0.06, -0.04, 1}, 0.05, 0.02),
                          dome_port({0.004, -0.003, 0.002}, 0.05, 0.008)};
    const Scene scenes[] = {plane({0, 0, 1}, 2.0), plane({0.4, -0.2, 1}, 2.5),
                            sphere({0.1, -0.05, 1.6}, 0.45)};
    const char* names[] = {"facing plane", "tilted plane", "sphere"};
    for (const Port& port : ports) {
        for (int i = 0; i < 3; ++i) {
            const HitErrors e = compare_hits(cam, port, scenes[i], 2.0);
            std::printf("%s port, %s: %ld pixels, position %.2e px, depth %.2e relative\n",
                        port.name(), names[i], e.checked, e.px, e.rel_z);
            EXPECT_GT(e.checked, 1000) << names[i];
            EXPECT_EQ(e.surface, e.checked) << names[i];
            EXPECT_LT(e.px, 0.05) << names[i];
            EXPECT_LT(e.rel_z, 1e-4) << names[i];
        }
    }
}

TEST(PortRender, FloatMarchAgreesWithTheDoubleMarch) {
    // The compositor's float march (PortRays::hit) and find_port_hit in double, from the same
    // traced ray: the same kind of hit everywhere, positions to float rounding, depths to float
    // rounding on the plane and to that times the surface's slope on the sphere (steep near its
    // rim, which is not left out here).
    const Camera cam = test_camera();
    const Port ports[] = {flat_port({0.06, -0.04, 1}, 0.05, 0.02),
                          dome_port({0.004, -0.003, 0.002}, 0.05, 0.008)};
    const Scene scenes[] = {plane({0.4, -0.2, 1}, 2.5), sphere({0.1, -0.05, 1.6}, 0.45)};
    const double depth_bar[] = {1e-5, 1e-4};
    for (const Port& port : ports) {
        const PortRays rays(port, cam);
        for (int i = 0; i < 2; ++i) {
            const Image z = depth_of(cam, scenes[i]);
            const Image inv = inverse_depth(z);
            const double z_near = nearest_surface(z);
            double px = 0, rel_z = 0;
            long surfaces = 0, differ = 0;
            for (int v = 0; v < cam.height; v += 2) {
                for (int u = 0; u < cam.width; u += 2) {
                    const PortRay r = trace_port(port, cam, u, v);
                    const Vec3& w = r.direction[1];
                    const PortHit d =
                        find_port_hit(cam, inv, project_ray(cam, r.origin, w), r.origin, w, z_near);
                    const PortHit f = rays.hit(u, v, inv, z_near);
                    if (d.kind != f.kind) {
                        ++differ;
                        continue;
                    }
                    if (d.kind != PortHitKind::Surface) continue;
                    ++surfaces;
                    px = std::max(px, std::hypot(d.u - f.u, d.v - f.v));
                    rel_z = std::max(rel_z, std::fabs(d.z - f.z) / d.z);
                }
            }
            std::printf(
                "%s port, scene %d: %ld surface hits, float against double: %.1e px, "
                "%.1e relative depth, %ld of another kind\n",
                port.name(), i, surfaces, px, rel_z, differ);
            EXPECT_GT(surfaces, 1000);
            EXPECT_EQ(differ, 0);
            EXPECT_LT(px, 1e-3);
            EXPECT_LT(rel_z, depth_bar[i]);
        }
    }
}

TEST(PortRender, CompositorRowsGiveTheScalarMarchsHits) {
    // port_row settles most rays in a march vectorised across the row (docs/port-speed.md)
    // and leaves the rest to the scalar march: its hit points must be the scalar march's
    // (PortRays::hit, what the tests above measure) bit for bit, with the same mask, on smooth
    // scenes and on one with depth edges and open water. Its x and y come from where the hit
    // projects, not from the ray: within float rounding of the double trace's point at the hit's
    // depth (1.5e-7 z at most here; reading the ray's origin and direction gave 1.3e-7 z).
    const Camera cam = test_camera();
    const Port ports[] = {flat_port({0, 0, 1}, 0.03, 0.012),
                          flat_port({0.06, -0.04, 1}, 0.05, 0.02),
                          dome_port({0.004, -0.003, 0.002}, 0.05, 0.008)};
    const Image depths[] = {depth_of(cam, plane({0.4, -0.2, 1}, 2.5)),
                            depth_of(cam, sphere({0.1, -0.05, 1.6}, 0.45)),
                            testing::plane_scene(cam).depth};
    // (normals and colour 0 here: only the hits are compared; the march reads the inverse depth)
    Image surface(cam.width, cam.height, kPortSurfaceChannels);
    const std::vector<float> zeros(3 * std::size_t(cam.width), 0.0f);
    std::vector<float> row_inv(cam.width), window_row(cam.width);
    std::vector<float> x(cam.width), y(cam.width), z(cam.width), t(cam.width), nx(cam.width),
        ny(cam.width), nz(cam.width), J(3 * cam.width), mask(cam.width);
    for (const Port& port : ports) {
        const PortRays rays(port, cam);
        for (const Image& depth : depths) {
            Image planar = depth;
            for (float& d : planar.data) d = has_surface(d) ? d : 0.0f;
            const Image inv = inverse_depth(planar);
            const double z_near = nearest_surface(planar);
            Image nearest, rows;
            window_nearest(inv, nearest, rows);
            for (int v = 0; v < cam.height; ++v) {
                port_depth_row(cam.width, planar.row(v), row_inv.data(), window_row.data());
                port_surface_row(cam.width, zeros.data(), zeros.data(), zeros.data(), zeros.data(),
                                 row_inv.data(), surface.row(v));
            }
            // The compositor makes normals and colour only within PortRays::reach: NaN beyond
            // it, which any tap read there, even with weight 0, would carry into the hits
            const PortRays::PixelBox box = rays.reach(1.001 / z_near);
            long outside = 0;
            for (int v = 0; v < cam.height; ++v) {
                for (int u = 0; u < cam.width; ++u) {
                    if (u >= box.x0 && u <= box.x1 && v >= box.y0 && v <= box.y1) continue;
                    float* p = surface.row(v) + std::size_t(u) * kPortSurfaceChannels;
                    for (int c : {0, 1, 2, 4, 5, 6}) p[c] = std::nanf("");
                    ++outside;
                }
            }
            long not_finite = 0;
            long differ = 0, surfaces = 0;
            double point_error = 0.0;  // the point's x and y against the double trace's, / z
            for (int v = 0; v < cam.height; ++v) {
                port_row(rays, v, inv, nearest, surface, z_near,
                         {x.data(), y.data(), z.data(), t.data(), nx.data(), ny.data(), nz.data(),
                          J.data(), mask.data()});
                for (int u = 0; u < cam.width; ++u) {
                    not_finite += !(std::isfinite(nx[u]) && std::isfinite(ny[u]) &&
                                    std::isfinite(nz[u]) && std::isfinite(J[3 * u]) &&
                                    std::isfinite(J[3 * u + 1]) && std::isfinite(J[3 * u + 2]));
                    const PortHit h = rays.hit(u, v, inv, z_near);
                    const bool surface_hit = h.kind == PortHitKind::Surface;
                    surfaces += surface_hit;
                    const bool same = mask[u] == (h.seen() ? 1.0f : 0.0f) &&
                                      z[u] == (surface_hit ? float(h.z) : 0.0f) &&
                                      t[u] == (surface_hit ? float(h.t) : 0.0f);
                    differ += !same;
                    if (!surface_hit || !same) continue;
                    // x and y come from where the hit projects: the point on the ray at z
                    const PortRay r = trace_port(port, cam, u, v);
                    const Vec3& w = r.direction[1];
                    const double along = (double(z[u]) - r.origin.z) / w.z;
                    const double ex = std::fabs(x[u] - (r.origin.x + along * w.x)),
                                 ey = std::fabs(y[u] - (r.origin.y + along * w.y));
                    point_error = std::max(point_error, std::max(ex, ey) / double(z[u]));
                }
            }
            EXPECT_EQ(differ, 0) << port.name();
            EXPECT_EQ(not_finite, 0) << port.name() << ": a tap beyond PortRays::reach";
            std::printf("%s: %ld of %d input pixels beyond reach\n", port.name(), outside,
                        cam.width * cam.height);
            EXPECT_LT(point_error, 4e-7) << port.name();
            EXPECT_GT(surfaces, 4000) << port.name();
        }
    }
}

TEST(PortRender, FlatPortShrinksThePlanesFootprintByThePredictedFactor) {
    // A thin flat port on the axis and a far plane facing the camera: each output pixel at
    // tan(a) = t sees the input at fx tan(w), tan(w) = t / sqrt(n^2 + (n^2 - 1) t^2).
    const Camera cam = test_camera();
    const Port port = flat_port({0, 0, 1}, 0.0, 1e-6);
    const double n = port.n_water.g / port.n_air;
    const PortRays rays(port, cam);
    const Image depth = inverse_depth(Image(cam.width, cam.height, 1, 500.0f));
    double worst = 0;
    for (int v = 0; v < cam.height; v += 7) {
        for (int u = 0; u < cam.width; u += 3) {
            const PortHit h = rays.hit(u, v, depth, 500.0);
            ASSERT_EQ(h.kind, PortHitKind::Surface);
            const double tx = (u - cam.cx) / cam.fx, ty = (v - cam.cy) / cam.fy;
            const double t = std::hypot(tx, ty);
            const double k = 1.0 / std::sqrt(n * n + (n * n - 1) * t * t);  // tan(w) / t
            worst = std::max(worst, std::hypot(h.u - (cam.cx + cam.fx * tx * k),
                                               h.v - (cam.cy + cam.fy * ty * k)));
        }
    }
    EXPECT_LT(worst, 0.01);
    // Rendered: a bright square of half-width 40 px in the input shows 40 / (fx k) wider...
    // in the output its edge lies where fx tan(w) = 40: t = n tan(w) / sqrt(1 - (n^2 - 1)
    // tan^2(w)).
    const double tw = 40.0 / cam.fx, t_edge = n * tw / std::sqrt(1 - (n * n - 1) * tw * tw);
    int inside = 0;
    for (int u = 0; u < cam.width; ++u) {
        const PortHit h = rays.hit(u, int(cam.cy), depth, 500.0);
        if (std::fabs(h.u - cam.cx) <= 40.0) ++inside;
    }
    EXPECT_NEAR(inside, 2 * cam.fx * t_edge, 1.0);
    std::printf(
        "a 80 px wide patch of the input: %d px in the output (predicted %.2f; 1 / n: "
        "%.2f)\n",
        inside, 2 * cam.fx * t_edge, 80.0 * n);
}

}  // namespace deepsea

namespace deepsea {

TEST(PortRender, MarchStartsOnlyWhereNothingNearerIsRead) {
    // A ray's march starts at its window's nearest surface (optics' port_start_window,
    // docs/port-speed.md): every input pixel its march can read must lie in that window, and
    // window_nearest must be the window's largest inverse depth. Checked on every pixel's ray of
    // three ports, the march's stretch of s sampled at 64 points (and its ends), each probe's
    // four taps (floor and floor + 1 of the clamped position, a thousandth of a pixel either
    // way); window_nearest against the maximum taken pixel by pixel on a random image.
    const Camera cam = test_camera();
    const int W = cam.width, H = cam.height, B = kPortStartBlock, bw = (W + B - 1) / B;
    Image inv(W, H, 1);
    std::srand(7);
    for (float& s : inv.data)
        s = std::rand() % 5 == 0 ? 0.0f : float(std::rand()) / float(RAND_MAX);
    Image nearest, rows;
    window_nearest(inv, nearest, rows);
    long windows = 0;
    for (int by = 0; by < nearest.height; ++by)
        for (int bx = 0; bx < nearest.width; ++bx) {
            float m = 0.0f;
            for (int y = std::max(B * (by - 1), 0); y < std::min(B * (by + 2), H); ++y)
                for (int x = std::max(B * (bx - 1), 0); x < std::min(B * (bx + 2), W); ++x)
                    m = std::max(m, inv.at(x, y));
            EXPECT_EQ(nearest.at(bx, by), m) << bx << ", " << by;
        }
    const Port ports[] = {flat_port({0, 0, 1}, 0.03, 0.012),
                          flat_port({0.06, -0.04, 1}, 0.05, 0.02),
                          dome_port({0.004, -0.003, 0.002}, 0.05, 0.008)};
    const float s_near = float(1.001 / 0.4);  // the frame's nearest surface 0.4 m away
    long outside = 0;
    for (const Port& port : ports) {
        const PortRays rays(port, cam);
        for (int v = 0; v < H; ++v)
            for (int u = 0; u < W; ++u) {
                const PortMarch<float> m = rays.march(u, v);
                const int w = port_start_window(m, s_near, W, H);
                if (w < 0) continue;
                ++windows;
                const int bx = w % bw, by = w / bw;
                const float hi = std::min(s_near, m.s_hi);
                for (int i = 0; i <= 64; ++i) {
                    const float s = m.s_lo + (hi - m.s_lo) * float(i) / 64;
                    for (const float e : {-1e-3f, 0.0f, 1e-3f}) {
                        const float pu = std::clamp(m.u_inf + m.du * s + e, 0.0f, float(W - 1));
                        const float pv = std::clamp(m.v_inf + m.dv * s + e, 0.0f, float(H - 1));
                        const int x0 = int(pu), y0 = int(pv);
                        outside += x0 < B * (bx - 1) || std::min(x0 + 1, W - 1) >= B * (bx + 2) ||
                                   y0 < B * (by - 1) || std::min(y0 + 1, H - 1) >= B * (by + 2);
                    }
                }
            }
    }
    EXPECT_EQ(outside, 0);
    EXPECT_GT(windows, 3 * W * H / 2);  // most rays start in their window
    std::printf("%ld of %d rays start at their window's nearest surface\n", windows, 3 * W * H);
}

TEST(PortRender, MarchRowTakesConstantsOnlyWhereTheyPickTheSame) {
    // The compositor's rows read s_lo, s_origin and s_hi from rows of constants (0, +inf, +inf)
    // where each ray's march picks the same with them (PortRays::march_row(v, s_near)): in a row
    // whose every ray has s_lo = +0 and s_near <= s_origin, s_hi. CompositorRowsGiveTheScalarMarchs
    // Hits checks the hits; this checks which rows take the constants. Where every ray's origin
    // depth oz has the same bits, the rows read it from a row of that value.
    const Camera cam = test_camera();
    const Port ports[] = {flat_port({0, 0, 1}, 0.03, 0.012), flat_port({1, 0, 1}, 0.03, 0.012),
                          dome_port({0.004, -0.003, 0.002}, 0.05, 0.008)};
    int constant_rows[3] = {0, 0, 0}, oz_rows[3] = {0, 0, 0}, k = 0;
    for (const Port& port : ports) {
        const PortRays rays(port, cam);
        for (const float s_near : {0.0f, 0.4f, 100.0f}) {
            for (int v = 0; v < cam.height; ++v) {
                const PortRays::MarchRow m = rays.march_row(v), c = rays.march_row(v, s_near);
                bool same = true;
                for (int u = 0; u < cam.width; ++u)
                    same = same && m.s_lo[u] == 0.0f && !std::signbit(m.s_lo[u]) &&
                           s_near <= m.s_origin[u] && s_near <= m.s_hi[u] && m.s_origin[u] > 0.0f;
                const bool constants = c.s_lo != m.s_lo;
                EXPECT_EQ(constants, same) << port.name() << " row " << v << " s_near " << s_near;
                if (constants) {
                    EXPECT_EQ(c.s_origin, c.s_hi);
                    EXPECT_EQ(c.s_lo[cam.width - 1], 0.0f);
                    EXPECT_EQ(c.s_hi[cam.width - 1], std::numeric_limits<float>::infinity());
                }
                EXPECT_EQ(c.u_inf, m.u_inf);
                EXPECT_EQ(c.dz, m.dz);
                for (int u = 0; u < cam.width; ++u) EXPECT_EQ(c.oz[u], m.oz[u]);
                constant_rows[k] += constants && s_near == 0.4f;
                oz_rows[k] += c.oz != m.oz && s_near == 0.4f;
            }
        }
        ++k;
    }
    // (the flat port on the axis at a frame's ordinary depths: every row; tilted 45 degrees,
    // beyond the half field of view, part of its rays leave the view before their vanishing point)
    EXPECT_EQ(constant_rows[0], cam.height);
    EXPECT_EQ(oz_rows[0], cam.height);  // (its outer surface is a plane z = const)
    EXPECT_EQ(oz_rows[2], 0);
    EXPECT_LT(constant_rows[1], cam.height);
    std::printf("rows with constants at s_near 0.4: flat %d, tilted flat %d, dome %d of %d\n",
                constant_rows[0], constant_rows[1], constant_rows[2], cam.height);
}

TEST(PortRender, GatherCellsReadsEachCellsFourPixels) {
    // The march's probes read their cells in a pass of their own (gather_cells, with AVX2 two
    // 8-byte loads a lane): each lane's four pixels, exactly, in groups of eight and in the tail.
    const int W = 37, H = 6, n = 8 * 5 + 3;
    Image inv(W, H, 1);
    for (std::size_t i = 0; i < inv.data.size(); ++i) inv.data[i] = 0.25f + float(i) * 1e-3f;
    std::vector<int> at(n);
    std::srand(11);
    for (int u = 0; u < n; ++u) at[u] = (std::rand() % (H - 1)) * W + std::rand() % (W - 1);
    at[0] = 0;
    at[n - 1] = (H - 2) * W + W - 2;  // the last cell
    std::vector<float> c[4];
    for (auto& v : c) v.assign(n, -1.0f);
    gather_cells(n, at.data(), inv.data.data(), W, c[0].data(), c[1].data(), c[2].data(),
                 c[3].data());
    for (int u = 0; u < n; ++u) {
        const float* p = inv.data.data() + at[u];
        EXPECT_EQ(c[0][u], p[0]) << u;
        EXPECT_EQ(c[1][u], p[1]) << u;
        EXPECT_EQ(c[2][u], p[W]) << u;
        EXPECT_EQ(c[3][u], p[W + 1]) << u;
    }
}

}  // namespace deepsea
