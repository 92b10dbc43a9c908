#pragma once
/// \file Small fixed-size vectors: Vec3 for geometry (metres, camera frame) and Rgb for
/// per-channel optical quantities (R, G, B).

#include <cmath>

namespace deepsea {

/// A 3-vector in the camera frame (OpenCV: x right, y down, z forward), metres.
struct Vec3 {
    double x = 0.0, y = 0.0, z = 0.0;

    constexpr Vec3() = default;
    constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

    constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
};

inline constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
inline constexpr double dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(const Vec3& v) { return std::sqrt(dot(v, v)); }
/// Unit vector along v; v must not be zero.
inline Vec3 normalize(const Vec3& v) { return v / length(v); }

/// Linear RGB triple: radiance, intensity, or a per-channel coefficient.
struct Rgb {
    double r = 0.0, g = 0.0, b = 0.0;

    constexpr Rgb() = default;
    constexpr Rgb(double r_, double g_, double b_) : r(r_), g(g_), b(b_) {}
    constexpr explicit Rgb(double v) : r(v), g(v), b(v) {}

    constexpr double operator[](int i) const { return i == 0 ? r : (i == 1 ? g : b); }
    double& operator[](int i) { return i == 0 ? r : (i == 1 ? g : b); }
    constexpr Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
    constexpr Rgb operator-(const Rgb& o) const { return {r - o.r, g - o.g, b - o.b}; }
    constexpr Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
    constexpr Rgb operator*(double s) const { return {r * s, g * s, b * s}; }
    constexpr Rgb operator/(double s) const { return {r / s, g / s, b / s}; }
    Rgb& operator+=(const Rgb& o) {
        r += o.r;
        g += o.g;
        b += o.b;
        return *this;
    }
    constexpr double max() const { return r > g ? (r > b ? r : b) : (g > b ? g : b); }
    constexpr double min() const { return r < g ? (r < b ? r : b) : (g < b ? g : b); }
};

inline constexpr Rgb operator*(double s, const Rgb& v) { return v * s; }
/// Per-channel exp: exp(Rgb{-c*d}) is the transmission over d metres.
inline Rgb exp(const Rgb& v) { return {std::exp(v.r), std::exp(v.g), std::exp(v.b)}; }

}  // namespace deepsea
