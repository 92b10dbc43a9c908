#include "deepsea/optics/camera_motion.h"

#include <cmath>

namespace deepsea {

namespace {

/// A unit quaternion w + (x, y, z).
struct Quat {
    double w, x, y, z;
};

Quat mul(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

Quat conj(const Quat& q) { return {q.w, -q.x, -q.y, -q.z}; }

/// The rotation whose matrix has the pose's axes as columns (Shepperd's method: the largest
/// of the four squared components first, for accuracy).
Quat quat_of(const CameraPose& p) {
    const double m00 = p.right.x, m10 = p.right.y, m20 = p.right.z;
    const double m01 = p.down.x, m11 = p.down.y, m21 = p.down.z;
    const double m02 = p.forward.x, m12 = p.forward.y, m22 = p.forward.z;
    const double tr = m00 + m11 + m22;
    Quat q;
    if (tr >= m00 && tr >= m11 && tr >= m22) {
        const double s = 2.0 * std::sqrt(1.0 + tr);
        q = {0.25 * s, (m21 - m12) / s, (m02 - m20) / s, (m10 - m01) / s};
    } else if (m00 >= m11 && m00 >= m22) {
        const double s = 2.0 * std::sqrt(1.0 + m00 - m11 - m22);
        q = {(m21 - m12) / s, 0.25 * s, (m01 + m10) / s, (m02 + m20) / s};
    } else if (m11 >= m22) {
        const double s = 2.0 * std::sqrt(1.0 + m11 - m00 - m22);
        q = {(m02 - m20) / s, (m01 + m10) / s, 0.25 * s, (m12 + m21) / s};
    } else {
        const double s = 2.0 * std::sqrt(1.0 + m22 - m00 - m11);
        q = {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25 * s};
    }
    const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    return {q.w / n, q.x / n, q.y / n, q.z / n};
}

/// The rotation's matrix columns as a pose's axes.
void set_axes(CameraPose& p, const Quat& q) {
    const double w = q.w, x = q.x, y = q.y, z = q.z;
    p.right = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)};
    p.down = {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)};
    p.forward = {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
}

}  // namespace

CameraPose interpolate_pose(const CameraPose& a, const CameraPose& b, double t) {
    if (t == 0.0) return a;
    const Quat qa = quat_of(a);
    Quat d = mul(conj(qa), quat_of(b));           // a's frame to b's
    if (d.w < 0.0) d = {-d.w, -d.x, -d.y, -d.z};  // the shorter arc
    const double s = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
    const double half = std::atan2(s, d.w);  // half the rotation angle
    Quat dt{1.0, 0.0, 0.0, 0.0};
    if (s > 0.0) {
        const double k = std::sin(t * half) / s;
        dt = {std::cos(t * half), d.x * k, d.y * k, d.z * k};
    }
    CameraPose p;
    p.origin = a.origin + (b.origin - a.origin) * t;
    set_axes(p, mul(qa, dt));
    return p;
}

Shutter shutter_poses(const CameraPose& pose, double t, const CameraPose& other, double t_other,
                      double exposure_s) {
    const double h = 0.5 * exposure_s / (t_other - t);
    return {interpolate_pose(pose, other, -h), interpolate_pose(pose, other, h)};
}

Vec3 to_world(const CameraPose& p, const Vec3& X) {
    return p.origin + p.right * X.x + p.down * X.y + p.forward * X.z;
}

}  // namespace deepsea
