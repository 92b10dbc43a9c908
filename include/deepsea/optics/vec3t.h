#pragma once
/// \file A 3-vector on any number type, for the per-pixel equations that the exact renderer
/// runs in double and the runtime's vectorised rows in float (lamp.h, normals.h). An
/// aggregate of three scalars, so that inside `#pragma omp simd` loops GCC keeps each
/// component in its own vector register.

#include "deepsea/core/vec.h"

namespace deepsea {

/// x, y, z in the camera frame (OpenCV: x right, y down, z forward), in the caller's units.
/// Functions take it by value. Inside a `#pragma omp simd` loop, pass temporaries, never a
/// named Vec3T declared in the loop body: GCC 12 keeps such a local in a per-lane array
/// ("omp simd array") and cannot vectorise the copy into a by-value argument, so the whole
/// loop stays scalar. Results (`const auto g = lamp_geometry(...)`) and loop-invariant
/// vectors declared before the loop are fine.
template <class T>
struct Vec3T {
    T x, y, z;
};

template <class T>
inline Vec3T<T> operator-(Vec3T<T> a, Vec3T<T> b) {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <class T>
inline Vec3T<T> operator*(Vec3T<T> a, T s) {
    return {a.x * s, a.y * s, a.z * s};
}
template <class T>
inline T dot(Vec3T<T> a, Vec3T<T> b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
inline Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/// The double geometry vector as a Vec3T, and back.
inline Vec3T<double> vec3t(const Vec3& v) { return {v.x, v.y, v.z}; }
inline Vec3 vec3(const Vec3T<double>& v) { return {v.x, v.y, v.z}; }

}  // namespace deepsea
