// The shared normal equations of normals.h (back-projection, same-surface test, normal from
// tangents), in double (the reference) and float (the runtime's rows).

#include "deepsea/optics/normals.h"

#include <gtest/gtest.h>

#include <cmath>

namespace deepsea {

namespace {

/// Planar depth of the plane n . X = -dist on the ray (rx, ry, 1).
double plane_z(const Vec3& n, double dist, double rx, double ry) {
    return -dist / dot(n, Vec3(rx, ry, 1.0));
}

/// The central-difference normal of pixel (rx, ry) of a plane, as the runtime forms it.
template <class T>
Vec3T<T> plane_normal(const Vec3& n, double rx, double ry, double h) {
    const auto p = [&](double x, double y) {
        return back_project(T(x), T(y), T(plane_z(n, 3.0, x, y)));
    };
    return normal_from_tangents(p(rx + h, ry) - p(rx - h, ry), p(rx, ry + h) - p(rx, ry - h),
                                Vec3T<T>{T(rx), T(ry), T(1)});
}

}  // namespace

TEST(BackProject, PlanarDepthAlongTheRay) {
    const Vec3T<double> P = back_project(0.5, -0.25, 4.0);
    EXPECT_EQ(P.x, 2.0);
    EXPECT_EQ(P.y, -1.0);
    EXPECT_EQ(P.z, 4.0);
}

TEST(SameSurface, FivePercentJump) {
    EXPECT_TRUE(same_surface(2.0, 2.09));
    EXPECT_TRUE(same_surface(2.0, 1.91));
    EXPECT_FALSE(same_surface(2.0, 2.11));
    EXPECT_FALSE(same_surface(2.0f, 1.8f));
}

TEST(NormalFromTangents, TiltedPlaneIsExact) {
    const Vec3 n = normalize(Vec3(0.3, -0.2, -1.0));  // faces the camera
    for (double rx : {-0.6, 0.0, 0.45}) {
        for (double ry : {-0.4, 0.1, 0.5}) {
            const Vec3T<double> d = plane_normal<double>(n, rx, ry, 1e-3);
            EXPECT_NEAR(d.x, n.x, 1e-12);
            EXPECT_NEAR(d.y, n.y, 1e-12);
            EXPECT_NEAR(d.z, n.z, 1e-12);
            // float: the same equation on float inputs, to float's rounding of the tangents
            const Vec3T<float> f = plane_normal<float>(n, rx, ry, 1e-2);
            EXPECT_NEAR(f.x, n.x, 1e-5);
            EXPECT_NEAR(f.y, n.y, 1e-5);
            EXPECT_NEAR(f.z, n.z, 1e-5);
        }
    }
}

TEST(NormalFromTangents, FacesTheCameraWhicheverWayTheTangentsTurn) {
    const Vec3T<double> tu{1, 0, 0}, tv{0, 1, 0}, r{0.1, 0.2, 1.0};
    const Vec3T<double> a = normal_from_tangents(tu, tv, r);
    const Vec3T<double> b = normal_from_tangents(tv, tu, r);
    EXPECT_EQ(a.z, -1.0);
    EXPECT_EQ(b.z, -1.0);
}

TEST(NormalFromTangents, ParallelTangentsGiveZero) {
    const Vec3T<double> t{1, 2, 3};
    const Vec3T<double> n = normal_from_tangents(t, t * 2.0, Vec3T<double>{0, 0, 1});
    EXPECT_EQ(dot(n, n), 0.0);
    const Vec3T<float> nf =
        normal_from_tangents(Vec3T<float>{0, 0, 0}, Vec3T<float>{1, 0, 0}, Vec3T<float>{0, 0, 1});
    EXPECT_EQ(dot(nf, nf), 0.0f);
}

}  // namespace deepsea
