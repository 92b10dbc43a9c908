// Rays through the camera housing's port (optics/port.h, docs/ports.md): Snell's law at each
// surface, the dome with the camera at its centre, the flat port's field of view, an angle-form
// trace and Fermat's principle as independent checks, total internal reflection, the radiance
// factor, the checks naming their keys and Refractive COLMAP's parameter lists.
#include "deepsea/optics/port.h"

#include <gtest/gtest.h>

#include <cmath>

#include "../message_of.h"
#include "deepsea/optics/schema.h"

namespace deepsea {
namespace {

const Camera kCam{160, 120, 120.0, 125.0, 79.5, 59.5};  // 67 x 51 degrees, 79 at the diagonal
const Camera kWide{160, 120, 60.0, 60.0, 79.5, 59.5};   // 106 x 90 degrees, 118 at the diagonal

Port flat_port() {
    Port p;
    p.kind = PortKind::Flat;
    p.flat = {{0.1, -0.05, 1.0}, 0.02, 0.012};  // tilted 6.4 degrees, not unit length
    p.n_glass = 1.52;
    p.n_water = {1.339, 1.342, 1.347};  // dispersive
    return p;
}

Port dome_port() {
    Port p;
    p.kind = PortKind::Dome;
    p.dome = {{0.004, -0.003, 0.006}, 0.05, 0.008};  // decentred by 7.8 mm
    p.n_water = {1.339, 1.342, 1.347};
    return p;
}

/// The surfaces' unit normals where the traced ray crosses them.
Vec3 inner_normal(const Port& p, const PortRay& r) {
    return p.kind == PortKind::Flat ? normalize(p.flat.normal) : normalize(r.inner - p.dome.centre);
}
Vec3 outer_normal(const Port& p, const PortRay& r) {
    return p.kind == PortKind::Flat ? normalize(p.flat.normal)
                                    : normalize(r.origin - p.dome.centre);
}

/// n1 sin(t1) - n2 sin(t2) and the triple product of d1, n, d2 (zero when coplanar).
void expect_snell(const Vec3& d1, const Vec3& d2, const Vec3& n, double n1, double n2,
                  const char* where) {
    EXPECT_NEAR(n1 * length(cross(d1, n)), n2 * length(cross(d2, n)), 1e-12) << where;
    EXPECT_NEAR(dot(cross(d1, n), d2), 0.0, 1e-12) << where;
    EXPECT_GT(dot(d1, n) * dot(d2, n), 0.0) << where;  // refracted, not reflected
    EXPECT_NEAR(length(d2), 1.0, 1e-14) << where;
}

TEST(Port, SnellsLawHoldsAtEachSurface) {
    for (const Port& p : {flat_port(), dome_port()}) {
        int traced = 0;
        for (double v = -0.5; v <= kCam.height - 0.5; v += 7.25)
            for (double u = -0.5; u <= kCam.width - 0.5; u += 9.5) {
                const PortRay r = trace_port(p, kCam, u, v);
                ASSERT_TRUE(r.valid()) << p.name() << " " << u << " " << v;
                const Vec3 ni = inner_normal(p, r), no = outer_normal(p, r);
                expect_snell(r.air, r.glass, ni, p.n_air, p.n_glass, "inner");
                for (int c = 0; c < 3; ++c)
                    expect_snell(r.glass, r.direction[c], no, p.n_glass, p.n_water[c], "outer");
                // The points lie on their surfaces, and the in-air ray is the pinhole's.
                EXPECT_NEAR(length(cross(r.air, normalize(kCam.ray(u, v)))), 0.0, 1e-15);
                if (p.kind == PortKind::Flat) {
                    EXPECT_NEAR(dot(r.inner, ni), p.flat.distance, 1e-15);
                    EXPECT_NEAR(dot(r.origin, no), p.flat.distance + p.flat.glass_thickness, 1e-15);
                } else {
                    EXPECT_NEAR(length(r.inner - p.dome.centre), p.dome.radius, 1e-15);
                    EXPECT_NEAR(length(r.origin - p.dome.centre),
                                p.dome.radius + p.dome.glass_thickness, 1e-15);
                }
                // Dispersion: blue (the largest index) bends toward the normal the most.
                EXPECT_LE(length(cross(r.direction[2], no)),
                          length(cross(r.direction[0], no)) + 1e-15);
                ++traced;
            }
        EXPECT_GT(traced, 200);
    }
}

TEST(Port, DomeWithTheCameraAtItsCentreLeavesRaysUnchanged) {
    Port p = dome_port();
    p.dome.centre = {0.0, 0.0, 0.0};
    p.n_water = Rgb(1.34);
    const double outer = p.dome.radius + p.dome.glass_thickness;
    for (double v = -0.5; v <= kCam.height - 0.5; v += 1.0)
        for (double u = -0.5; u <= kCam.width - 0.5; u += 1.0) {
            const PortRay r = trace_port(p, kCam, u, v);
            ASSERT_TRUE(r.valid());
            const Vec3 d = normalize(kCam.ray(u, v));
            for (int c = 0; c < 3; ++c) EXPECT_LE(length(r.direction[c] - d), 1e-15) << u << v;
            EXPECT_LE(length(r.origin - d * outer), 1e-15 * outer);
            EXPECT_NEAR(length(r.origin), outer, 1e-15 * outer);
        }
}

// Flat port, normal along the optical axis: the surfaces are parallel, so Snell's law at both
// gives n_air sin(a) = n_glass sin(g) = n_water sin(w), whatever the glass. A ray at tan(a) = t
// from the axis has sin(a) = t / sqrt(1 + t^2), and with n = n_water / n_air
//     tan(w) = sin(w) / sqrt(1 - sin^2(w)) = t / sqrt(n^2 + (n^2 - 1) t^2),
// t / n for small t: the field of view shrinks by about the water's index, more at the edges.
TEST(Port, FlatPortShrinksTheFieldOfViewByThePredictedFactor) {
    const Camera cam{800, 600, 600.0, 600.0, 399.5, 299.5};
    for (const double thickness : {1e-9, 0.01, 0.03}) {
        Port p;
        p.flat = {{0.0, 0.0, 1.0}, 0.015, thickness};
        p.n_air = 1.0;
        p.n_water = Rgb(1.34);
        const double n = p.n_water.g / p.n_air;
        for (const double u : {-0.5, cam.width - 0.5}) {
            const double t = std::fabs(cam.ray_x(u));  // 400 / 600
            const PortRay r = trace_port(p, cam, u, cam.cy);
            ASSERT_TRUE(r.valid());
            const Vec3 w = r.direction[1];
            const double predicted = t / std::sqrt(n * n + (n * n - 1.0) * t * t);
            EXPECT_NEAR(std::fabs(w.x / w.z), predicted, 1e-14);
            EXPECT_EQ(w.y, 0.0);
        }
        const double t = 400.0 / 600.0;
        const double fov_air = 2.0 * std::atan(t);
        const double fov_water = 2.0 * std::atan(t / std::sqrt(n * n + (n * n - 1.0) * t * t));
        const PortRay left = trace_port(p, cam, -0.5, cam.cy);
        const PortRay right = trace_port(p, cam, cam.width - 0.5, cam.cy);
        const double traced = std::acos(dot(left.direction[1], right.direction[1]));
        EXPECT_NEAR(traced / fov_air, fov_water / fov_air, 1e-12);
        // 67.4 degrees in air, 48.9 in water: 0.726, below the small-angle factor 1 / n = 0.746.
        EXPECT_NEAR(fov_water / fov_air, 0.7258, 1e-4);
    }
}

// Independent of the vector form: the angles of each segment from Snell's law in sines (asin),
// the offsets along the surface from their tangents, in the plane of the ray and the normal.
TEST(Port, FlatPortAgreesWithAnAngleFormTrace) {
    for (const Vec3 normal : {Vec3{0, 0, 1}, Vec3{0.1, -0.05, 1.0}, Vec3{-0.3, 0.2, 1.0}}) {
        Port p = flat_port();
        p.flat.normal = normal;
        const Vec3 n = normalize(normal);
        for (double v = -0.5; v <= kCam.height - 0.5; v += 11.5)
            for (double u = -0.5; u <= kCam.width - 0.5; u += 13.5) {
                const Vec3 d = normalize(kCam.ray(u, v));
                const Vec3 along = d - n * dot(d, n);  // in the surface, the plane of incidence
                const double sin_a = length(along);
                const Vec3 e = sin_a > 0 ? along / sin_a : Vec3{};
                const double a = std::asin(sin_a);
                const double g = std::asin(p.n_air * sin_a / p.n_glass);
                const Vec3 inner = n * p.flat.distance + e * (p.flat.distance * std::tan(a));
                const Vec3 origin =
                    inner + n * p.flat.glass_thickness + e * (p.flat.glass_thickness * std::tan(g));
                const PortRay r = trace_port(p, kCam, u, v);
                ASSERT_TRUE(r.valid());
                EXPECT_LE(length(r.inner - inner), 1e-9);
                EXPECT_LE(length(r.origin - origin), 1e-9);
                for (int c = 0; c < 3; ++c) {
                    const double w = std::asin(p.n_air * sin_a / p.n_water[c]);
                    const Vec3 dir = n * std::cos(w) + e * std::sin(w);
                    EXPECT_LE(length(r.direction[c] - dir), 1e-9) << u << " " << v;
                }
            }
    }
}

/// Optical path length from the camera centre through x1 and x2 to the water point q.
double optical_path(const Port& p, const Vec3& x1, const Vec3& x2, const Vec3& q, int c) {
    return p.n_air * length(x1) + p.n_glass * length(x2 - x1) + p.n_water[c] * length(q - x2);
}

// Fermat's principle, independent of Snell's law: among paths from the camera centre through
// the two surfaces to a point in the water, the traced one has a stationary optical path
// length. Each crossing point is moved along its surface in two directions, by +-1e-6 m
// (central differences; Richardson's extrapolation with +-2e-6 m removes the e^2 term): the
// derivative of the path length is 0 to 1e-9. The flat port's path, a sum of norms of affine
// functions of the crossing points, is moreover a minimum: moving a point by 1e-4 m lengthens it.
TEST(Port, TracedPathIsStationaryByFermatsPrinciple) {
    for (const Port& p : {flat_port(), dome_port()}) {
        for (const auto& [u, v] : {std::pair{-0.5, -0.5}, std::pair{30.0, 100.0},
                                   std::pair{159.5, 60.0}, std::pair{79.5, 59.5}}) {
            const PortRay r = trace_port(p, kCam, u, v);
            ASSERT_TRUE(r.valid());
            for (int c = 0; c < 3; ++c) {
                const Vec3 q = r.origin + r.direction[c] * 0.7;
                for (int surface = 0; surface < 2; ++surface) {
                    const Vec3 x = surface == 0 ? r.inner : r.origin;
                    const Vec3 n = surface == 0 ? inner_normal(p, r) : outer_normal(p, r);
                    const Vec3 t1 = normalize(cross(n, Vec3{1, 0, 0}));
                    const Vec3 t2 = cross(n, t1);
                    const auto moved = [&](const Vec3& dir, double e) {
                        const Vec3 y = x + dir * e;
                        if (p.kind == PortKind::Flat) return y;
                        const double radius = length(x - p.dome.centre);
                        return p.dome.centre + normalize(y - p.dome.centre) * radius;
                    };
                    const auto path = [&](const Vec3& dir, double e) {
                        return surface == 0 ? optical_path(p, moved(dir, e), r.origin, q, c)
                                            : optical_path(p, r.inner, moved(dir, e), q, c);
                    };
                    const double base = path(t1, 0.0);
                    for (const Vec3& dir : {t1, t2}) {
                        const double h = 1e-6;
                        const double d1 = (path(dir, h) - path(dir, -h)) / (2 * h);
                        const double d2 = (path(dir, 2 * h) - path(dir, -2 * h)) / (4 * h);
                        EXPECT_NEAR((4 * d1 - d2) / 3, 0.0, 1e-9) << p.name() << " " << u;
                        if (p.kind == PortKind::Flat) {
                            EXPECT_GT(path(dir, 1e-4), base);
                            EXPECT_GT(path(dir, -1e-4), base);
                        }
                    }
                }
            }
        }
    }
}

TEST(Port, TotalInternalReflectionIsDetected) {
    // Glass to air at 45 degrees: sin = 0.707 > 1 / 1.5.
    const double s = std::sqrt(0.5);
    Vec3T<double> t{7, 7, 7};
    EXPECT_FALSE(refract<double>({s, 0, s}, {0, 0, 1}, 1.5, 1.0, t));
    EXPECT_EQ(t.x, 7.0);                                               // untouched
    EXPECT_TRUE(refract<double>({s, 0, s}, {0, 0, -1}, 1.0, 1.5, t));  // either orientation
    EXPECT_NEAR(t.x, s / 1.5, 1e-15);
    EXPECT_GT(t.z, 0.0);
    // A housing full of water looking into air: the corners reflect, the centre does not.
    Port p;
    p.flat = {{0, 0, 1}, 0.01, 0.01};
    p.n_air = 1.33;
    p.n_water = Rgb(1.0);
    EXPECT_EQ(trace_port(p, kWide, -0.5, -0.5).status, PortRayStatus::OuterReflection);
    EXPECT_TRUE(trace_port(p, kWide, 79.5, 59.5).valid());
    EXPECT_EQ(port_radiance_factor(p, trace_port(p, kWide, -0.5, -0.5)).g, 0.0);
    // Glass below the air's index reflects at the inner surface.
    p.n_air = 1.0;
    p.n_water = Rgb(1.34);
    p.n_glass = 0.8;
    EXPECT_EQ(trace_port(p, kWide, -0.5, -0.5).status, PortRayStatus::InnerReflection);
    // Only the channel whose index is too low fails.
    p.n_glass = 1.5;
    p.n_air = 1.33;
    p.n_water = {1.0, 1.34, 1.34};
    EXPECT_EQ(trace_port(p, kWide, -0.5, -0.5).status, PortRayStatus::OuterReflection);
    p.n_water = {1.34, 1.34, 1.34};
    EXPECT_TRUE(trace_port(p, kWide, -0.5, -0.5).valid());
}

TEST(Port, RadianceFactorIsTheNSquaredLawTimesFresnel) {
    Port p = dome_port();
    p.dome.centre = {0, 0, 0};  // every ray at normal incidence
    for (const bool fresnel : {false, true}) {
        p.fresnel = fresnel;
        for (const auto& [u, v] : {std::pair{-0.5, -0.5}, std::pair{79.5, 59.5}}) {
            const Rgb f = port_radiance_factor(p, trace_port(p, kCam, u, v));
            for (int c = 0; c < 3; ++c) {
                const double nw = p.n_water[c];
                double expected = (p.n_air / nw) * (p.n_air / nw);
                if (fresnel) {
                    const double r1 = (p.n_glass - p.n_air) / (p.n_glass + p.n_air);
                    const double r2 = (nw - p.n_glass) / (nw + p.n_glass);
                    expected *= (1 - r1 * r1) * (1 - r2 * r2);
                }
                EXPECT_NEAR(f[c], expected, 1e-15) << fresnel << " " << c;
            }
        }
    }
    // Equal indices: no interface at all, factor 1 at any angle; Fresnel falls off with angle.
    Port same = flat_port();
    same.n_air = same.n_glass = 1.3;
    same.n_water = Rgb(1.3);
    same.fresnel = true;
    EXPECT_NEAR(port_radiance_factor(same, trace_port(same, kCam, -0.5, -0.5)).r, 1.0, 1e-15);
    Port f = flat_port();
    f.fresnel = true;
    EXPECT_LT(port_radiance_factor(f, trace_port(f, kCam, -0.5, -0.5)).g,
              port_radiance_factor(f, trace_port(f, kCam, 79.5, 59.5)).g);
}

std::string error_of(const Port& p, const Camera& cam = kCam) {
    return test::message_of<SchemaError>([&] {
        validate(p);
        check_port_view(p, cam);
    });
}

std::string key_of(const Port& p, const Camera& cam = kCam) {
    try {
        validate(p);
        check_port_view(p, cam);
    } catch (const SchemaError& e) {
        return e.key();
    }
    return "";
}

TEST(Port, ImpossiblePortsNameTheKey) {
    Port p = flat_port();
    EXPECT_EQ(key_of(p), "");
    EXPECT_EQ(key_of(dome_port()), "");
    p.flat.glass_thickness = 0.0;
    EXPECT_EQ(error_of(p), "camera.port.flat.glass_thickness: must be > 0, got 0");
    p = flat_port();
    p.flat.distance = -0.01;
    EXPECT_EQ(error_of(p), "camera.port.flat.distance: must be >= 0, got -0.01");
    p.flat.distance = 11.0;
    EXPECT_EQ(key_of(p), "camera.port.flat.distance");
    p = flat_port();
    for (const Vec3 bad : {Vec3{0, 0, 0}, Vec3{0, std::nan(""), 1}, Vec3{1e300, 1e300, 0}}) {
        p.flat.normal = bad;
        EXPECT_EQ(key_of(p), "camera.port.flat.normal");
    }
    p = flat_port();
    p.n_air = 0.0;
    EXPECT_EQ(error_of(p), "camera.port.flat.n_air: must be > 0 and finite, got 0");
    p = flat_port();
    p.n_glass = -1.5;
    EXPECT_EQ(key_of(p), "camera.port.flat.n_glass");
    p = flat_port();
    p.n_water.g = 0.0;
    EXPECT_EQ(error_of(p), "camera.port.flat.n_water: must be > 0 and finite (G is 0)");
    // Behind the camera: facing backwards, or tilted so far that the corners miss it.
    p = flat_port();
    p.flat.normal = {0, 0, -1};
    EXPECT_EQ(key_of(p), "camera.port.flat.normal");
    p.flat.normal = {1, 0, 0.5};  // 63 degrees: the left edge's rays run away from the plane
    const std::string behind = error_of(p);
    EXPECT_NE(behind.find("camera.port.flat.normal: the interface is behind the camera for the "
                          "ray through image point (u, v) = (-0.5, -0.5)"),
              std::string::npos)
        << behind;
    // The dome: the camera outside it, a zero radius or thickness.
    Port d = dome_port();
    d.dome.centre = {0, 0, 0.05};
    EXPECT_EQ(error_of(d),
              "camera.port.dome.centre: puts the camera centre outside the dome: |centre| = "
              "0.05 m >= radius = 0.05 m (the inner surface's radius); the camera must be inside");
    d = dome_port();
    d.dome.radius = 0.0;
    EXPECT_EQ(error_of(d), "camera.port.dome.radius: must be > 0, got 0");
    d = dome_port();
    d.dome.glass_thickness = -0.001;
    EXPECT_EQ(key_of(d), "camera.port.dome.glass_thickness");
    // Total internal reflection over part of the view names the index of that surface.
    p = flat_port();
    p.n_air = 1.33;
    p.n_water = {1.34, 1.0, 1.34};
    const std::string tir = error_of(p, kWide);
    EXPECT_EQ(tir.rfind("camera.port.flat.n_water: total internal reflection at the outer surface "
                        "(glass to water) for the ray through image point (u, v) = ",
                        0),
              0u)
        << tir;
    EXPECT_NE(tir.find("> n_water = 1 (G)"), std::string::npos) << tir;
    p = flat_port();
    p.n_glass = 0.6;
    EXPECT_EQ(key_of(p, kWide), "camera.port.flat.n_glass");
    // A narrow camera keeps the same port inside its limits: the check is over the view.
    EXPECT_EQ(key_of(p, Camera{16, 12, 600.0, 600.0, 7.5, 5.5}), "");
    // One line each.
    EXPECT_EQ(tir.find('\n'), std::string::npos);
}

TEST(Port, RefractiveColmapParameterLists) {
    const Port f = flat_port();
    const std::vector<double> fp = colmap_params(f);
    ASSERT_EQ(fp.size(), 8u);
    EXPECT_NEAR(fp[0] * fp[0] + fp[1] * fp[1] + fp[2] * fp[2], 1.0, 1e-15);  // unit normal
    EXPECT_EQ(fp[3], 0.02);
    EXPECT_EQ(fp[4], 0.012);
    EXPECT_EQ(fp[6], 1.52);
    EXPECT_EQ(fp[7], 1.342);  // nw: the green channel's
    const Port back = port_from_colmap("FLATPORT", fp);
    EXPECT_EQ(back.kind, PortKind::Flat);
    const PortRay a = trace_port(f, kCam, 3, 4), b = trace_port(back, kCam, 3, 4);
    EXPECT_LE(length(a.origin - b.origin), 1e-15);
    EXPECT_LE(length(a.direction[1] - b.direction[1]), 1e-15);
    const Port d = port_from_colmap("DOMEPORT", colmap_params(dome_port()));
    EXPECT_EQ(d.kind, PortKind::Dome);
    EXPECT_EQ(d.dome.centre.y, -0.003);
    EXPECT_EQ(d.dome.radius, 0.05);
    EXPECT_EQ(d.dome.glass_thickness, 0.008);
    EXPECT_EQ(d.n_water.b, 1.342);
    EXPECT_THROW(port_from_colmap("SPHEREPORT", fp), ConfigError);
    EXPECT_THROW(port_from_colmap("DOMEPORT", {1, 2, 3}), ConfigError);
}

}  // namespace
}  // namespace deepsea
