#pragma once
// Internal: the camera stage's row kernels (rows.cpp, vectorised with -ffast-math and an AVX2
// clone) and the aligned scratch they work in. A row is processed as its 3 x width interleaved
// values in a flat loop; its arithmetic runs on 64-byte aligned buffers only, so that the
// vectoriser splits every row the same way and a pixel's bits never depend on where a
// thread's buffers happen to lie.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>

#include "deepsea/camera/model.h"
#include "deepsea/camera/noise.h"

namespace deepsea::camera_rows {

/// 64-byte aligned memory, uninitialised.
struct AlignedBytes {
    struct Free {
        void operator()(unsigned char* p) const { ::operator delete[](p, std::align_val_t(64)); }
    };
    std::unique_ptr<unsigned char[], Free> data;

    explicit AlignedBytes(std::size_t n = 0)
        : data(n ? static_cast<unsigned char*>(::operator new[](n, std::align_val_t(64)))
                 : nullptr) {}
    /// n objects of T at byte `offset` (a multiple of 64).
    template <class T>
    T* at(std::size_t offset) const {
        return reinterpret_cast<T*>(data.get() + offset);
    }
};

/// Bytes for n values of T, rounded up to whole cache lines.
template <class T>
std::size_t line_bytes(std::size_t n) {
    return (n * sizeof(T) + 63) / 64 * 64;
}

/// What the sensor kernel needs for one frame.
struct SensorParams {
    int width = 0;
    float exposure_time_ms = 0;  ///< the response row is per millisecond
    float dark_electrons = 0;    ///< mean dark-current electrons
    float full_well = 0, gain = 0, black = 0, max_dn = 0;
    float read_noise = 0;  ///< electrons
    bool noise = true;
    NoiseKey shot_key, read_key;
};

/// One row's buffers, 3 x width interleaved values each (aligned).
struct RowBuffers {
    const float* radiance;  ///< the row's radiance
    const float* response;  ///< the camera's: mean electrons per unit radiance and millisecond
    const float* dsnu;      ///< the camera's: dark signal offset, electrons
    float* mean;            ///< scratch: Poisson mean (photo + dark electrons)
    std::int32_t* flag;     ///< scratch: 1 where the value takes the exact path
    float* raw;             ///< out: DN as read out (clipped, quantised)
    float* linear;          ///< out: DN before clipping and quantisation
    // The exact path's values, gathered: index, mean, uniform, electrons, DSNU + read noise.
    std::int32_t* index;
    float *exact_mean, *exact_uniform, *exact_electrons, *exact_offset;
};

/// Row v: radiance to DN (docs/camera.md, "Noise").
void sensor_row(const SensorParams& p, int v, const RowBuffers& b);

/// Row v without noise, for the noise-free image: K min(mean, full well) + black, clipped to
/// the DN range, from the noise-free response (falloff x channel response, per millisecond).
void noise_free_row(const SensorParams& p, const float* radiance, const float* response, float* dn);

/// Each value's mean electrons per unit radiance: the falloff at x2[u] + y2 times resp[c].
void gain_row(const Vignetting& vig, const float* x2, float y2, const float resp[3], int width,
              float* gain);

/// What the processing kernel needs (per-channel scales come as a row, `scale`).
struct ProcessParams {
    int width = 0;
    float black = 0;
    bool matrix = false;
    float m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    OutputCurve curve = OutputCurve::Linear;
    float inv_gamma = 1;
};

/// DN (3 x width interleaved) to display values: (dn - black) scale, the matrix, clamp to
/// [0, 1], the curve. `tmp` is scratch of the same size; out may be dn.
void process_row(const ProcessParams& p, const float* scale, const float* dn, float* tmp,
                 float* out);

}  // namespace deepsea::camera_rows
