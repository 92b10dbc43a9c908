#pragma once
/// \file Real spherical harmonics up to order 2 (9 coefficients) and the irradiance they give a
/// Lambertian surface (Ramamoorthi & Hanrahan 2001, "An efficient representation for
/// irradiance environment maps"). Templated on the number type: the baker projects in double,
/// the runtime evaluates rows of pixels in float.

namespace deepsea {

/// Coefficients per colour channel.
inline constexpr int kShCount = 9;

/// The 9 real SH basis functions Y_lm at the unit vector (x, y, z), in the order
/// (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1), (2,2).
template <typename T>
inline void sh_basis(T x, T y, T z, T* Y) {
    Y[0] = T(0.282094791773878);
    Y[1] = T(0.488602511902920) * y;
    Y[2] = T(0.488602511902920) * z;
    Y[3] = T(0.488602511902920) * x;
    Y[4] = T(1.092548430592079) * x * y;
    Y[5] = T(1.092548430592079) * y * z;
    Y[6] = T(0.315391565252520) * (T(3) * z * z - T(1));
    Y[7] = T(1.092548430592079) * x * z;
    Y[8] = T(0.546274215296040) * (x * x - y * y);
}

/// The clamped-cosine kernel's SH factors A_l (pi, 2 pi / 3, pi / 4) for each coefficient:
/// E(n) = sum_m A_l(m) L_m Y_m(n) is the irradiance integral of L(d) max(0, n . d) over the
/// sphere, for radiance L(d) arriving from direction d (unit vector toward where the light
/// comes from) given by its SH coefficients L_m.
template <typename T>
inline T sh_cosine_factor(int m) {
    return m == 0 ? T(3.141592653589793) : (m < 4 ? T(2.094395102393195) : T(0.785398163397448));
}

/// Irradiance (W/m^2 per unit of the coefficients' radiance) onto a surface with unit normal
/// (nx, ny, nz) from one channel's 9 coefficients L.
template <typename T>
inline T sh_irradiance(const T* L, T nx, T ny, T nz) {
    T Y[kShCount];
    sh_basis(nx, ny, nz, Y);
    T e = T(0);
    for (int m = 0; m < kShCount; ++m) e += sh_cosine_factor<T>(m) * L[m] * Y[m];
    return e;
}

}  // namespace deepsea
