#pragma once
/// \file How a camera moves during one exposure (docs/snow-shadows.md, "Motion streaks"): poses
/// in between and beyond two known ones (centre lerp, orientation slerp) and the poses at which
/// a frame's shutter opens and closes. Pure functions on CameraPose (optics/snow.h).

#include "deepsea/optics/snow.h"

namespace deepsea {

/// A camera's poses (camera to world) when its shutter opens and when it closes.
struct Shutter {
    CameraPose open;
    CameraPose close;
};

/// The pose a fraction t of the way from a to b at constant velocity: the centre linearly,
/// the orientation by spherical linear interpolation of the shorter arc (t outside [0, 1]:
/// extrapolated at the same linear and angular velocity). t = 0 gives a, t = 1 gives b (to
/// rounding).
CameraPose interpolate_pose(const CameraPose& a, const CameraPose& b, double t);

/// The shutter of a frame taken at time t (seconds) with pose `pose`, exposed for
/// `exposure_s` seconds centred on t, with the camera's velocity that of the move between
/// `pose` and `other`, the pose of a neighbouring frame at time t_other != t (before or after).
Shutter shutter_poses(const CameraPose& pose, double t, const CameraPose& other, double t_other,
                      double exposure_s);

/// The point whose camera-frame coordinates under `pose` are X, in the world.
Vec3 to_world(const CameraPose& pose, const Vec3& X);

/// A world point's camera-frame coordinates under `pose` (inline: marine snow places every
/// particle with it).
inline Vec3 to_camera(const CameraPose& pose, const Vec3& world) {
    const Vec3 d = world - pose.origin;
    return {dot(d, pose.right), dot(d, pose.down), dot(d, pose.forward)};
}

}  // namespace deepsea
