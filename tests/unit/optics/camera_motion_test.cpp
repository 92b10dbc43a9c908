// Poses between and beyond two known ones (optics/camera_motion.h): the ends come back, the
// rotation angle grows linearly about one fixed axis, the centre linearly, and a frame's shutter
// poses are the constant-velocity poses half an exposure either side, from a neighbour before
// or after.

#include "deepsea/optics/camera_motion.h"

#include <gtest/gtest.h>

#include <cmath>

namespace deepsea {

namespace {

/// A rotation by `angle` about unit `axis` applied to the pose `p`'s axes (Rodrigues).
CameraPose rotated(const CameraPose& p, const Vec3& axis, double angle, const Vec3& origin) {
    const auto rot = [&](const Vec3& v) {
        return v * std::cos(angle) + cross(axis, v) * std::sin(angle) +
               axis * (dot(axis, v) * (1 - std::cos(angle)));
    };
    return {origin, rot(p.right), rot(p.down), rot(p.forward)};
}

/// The angle of the rotation taking a's axes to b's.
double angle_between(const CameraPose& a, const CameraPose& b) {
    const double tr = dot(a.right, b.right) + dot(a.down, b.down) + dot(a.forward, b.forward);
    return std::acos(std::clamp((tr - 1) / 2, -1.0, 1.0));
}

void expect_pose(const CameraPose& a, const CameraPose& b, double tol) {
    for (const auto& [x, y] : {std::pair{a.origin, b.origin}, std::pair{a.right, b.right},
                               std::pair{a.down, b.down}, std::pair{a.forward, b.forward}})
        EXPECT_LT(length(x - y), tol);
}

const CameraPose kStart =
    rotated(CameraPose{}, normalize(Vec3{0.3, 1.0, -0.2}), 0.7, Vec3{1.0, -2.0, 0.5});
const Vec3 kAxis = normalize(Vec3{-0.5, 0.2, 1.0});

}  // namespace

TEST(CameraMotion, InterpolationIsConstantVelocity) {
    for (const double total : {1e-4, 0.3, 2.5}) {
        const CameraPose b = rotated(kStart, kAxis, total, {1.5, -1.0, 0.9});
        expect_pose(interpolate_pose(kStart, b, 0.0), kStart, 1e-15);
        expect_pose(interpolate_pose(kStart, b, 1.0), b, 1e-12);
        for (const double t : {-0.4, 0.25, 0.5, 1.2}) {
            const CameraPose p = interpolate_pose(kStart, b, t);
            // About the same axis, by t of the angle; the centre on the line.
            expect_pose(
                p,
                rotated(kStart, kAxis, t * total, kStart.origin + (b.origin - kStart.origin) * t),
                1e-12);
            EXPECT_NEAR(angle_between(kStart, p), std::fabs(t) * total, 1e-7);
            EXPECT_NEAR(dot(p.right, p.down), 0.0, 1e-12);
            EXPECT_NEAR(length(p.forward), 1.0, 1e-12);
        }
    }
}

TEST(CameraMotion, ShutterIsHalfAnExposureEitherSide) {
    const double rate = 0.4;       // rad/s
    const Vec3 v{0.8, -0.1, 0.3};  // m/s
    const auto at = [&](double t) {
        return rotated(kStart, kAxis, rate * t, kStart.origin + v * t);
    };
    const double t = 2.0, e = 0.02;
    for (const double other : {t - 1.0 / 30, t + 1.0 / 15}) {
        const Shutter s = shutter_poses(at(t), t, at(other), other, e);
        expect_pose(s.open, at(t - e / 2), 1e-9);
        expect_pose(s.close, at(t + e / 2), 1e-9);
    }
}

TEST(CameraMotion, WorldAndCameraAreInverse) {
    const Vec3 X{0.3, -0.7, 2.1};
    EXPECT_LT(length(to_camera(kStart, to_world(kStart, X)) - X), 1e-12);
    EXPECT_LT(length(to_world(kStart, X) - (kStart.origin + kStart.forward * 2.1 +
                                            kStart.right * 0.3 - kStart.down * 0.7)),
              1e-12);
}

}  // namespace deepsea
