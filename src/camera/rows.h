#pragma once
// Internal: the camera stage's row kernels (rows.cpp, vectorised with -ffast-math and an AVX2
// clone) and the aligned scratch they work in. A row is processed as its 3 x width interleaved
// values in a flat loop; its arithmetic runs on 64-byte aligned buffers only, so that the
// vectoriser splits every row the same way and a pixel's bits never depend on where a
// thread's buffers happen to lie.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <memory>
#include <new>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

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

/// Values (3 per pixel) per chunk: a row is recorded in chunks of this many so that a chunk's
/// scratch (a dozen arrays, 1.5 KB each) stays in L1 from the sensor to the image. A multiple of
/// 3 (whole pixels) and of 16 (chunks start on cache lines, so every chunk of every row is
/// split into vectors the same way, whatever thread runs it).
inline constexpr int kChunk = 384;

/// Floats per row of the stage's per-value arrays: 3 x width rounded up to a cache line, so that
/// every row (and chunk) starts 64-byte aligned.
inline std::size_t row_stride(int width) { return (3 * std::size_t(width) + 15) / 16 * 16; }

/// What the sensor kernel needs for one frame.
struct SensorParams {
    float exposure_time_ms = 0;  ///< the response row is per millisecond
    float dark_electrons = 0;    ///< mean dark-current electrons
    float full_well = 0, gain = 0, black = 0, max_dn = 0;
    float read_noise = 0;  ///< electrons
    /// Means below it take the Poisson path (poisson_below(read_noise), noise.h).
    float poisson_below = float(kGaussianShotNoiseFrom);
    bool noise = true;
    bool keep_linear = false;  ///< fill RowBuffers::linear (else it is not touched)
    /// Fill RowBuffers::raw for every value. False: where the image is made in the sensor's
    /// loop (RowBuffers::lut or code_lut), only the exact path's values (what the image's
    /// fix-up reads); the others are not touched.
    bool keep_raw = true;
    NoiseKey shot_key, read_key;
};

/// One chunk's buffers, n interleaved values each (aligned, n <= kChunk).
struct RowBuffers {
    const float* radiance;  ///< the chunk's radiance
    const float* response;  ///< the camera's: mean electrons per unit radiance and millisecond
    const float* dsnu;      ///< the camera's: dark signal offset, electrons
    /// With a Bayer mosaic, 1 where the value's channel is the one its pixel records (else
    /// null): the others take no exact path and read out 0.
    const std::int32_t* record;
    float* normal;       ///< scratch: the shot stream's normal deviates (normal_row)
    float* mean;         ///< scratch: Poisson mean (photo + dark electrons)
    std::int32_t* flag;  ///< scratch: 1 where the value takes the exact path
    float* raw;          ///< out: DN as read out (clipped, quantised)
    float* linear;       ///< out: DN before clipping and quantisation (if keep_linear)
    // The exact path's values, gathered: index, mean, uniform, electrons, DSNU + read noise.
    std::int32_t* index;
    float *exact_mean, *exact_uniform, *exact_electrons, *exact_offset;
    /// Optional, only where reads_unaligned: the image made in the sensor's loop through the
    /// frame's table of display values (`lut` into `shown`) or of 8-bit codes (`code_lut` into
    /// `codes`), entry 3 dn + c as lookup_row's (null: not made here).
    const float* lut = nullptr;
    float* shown = nullptr;
    const std::uint8_t* code_lut = nullptr;
    std::uint8_t* codes = nullptr;
};

/// One task's chunk buffers (kChunk values each) for the camera stage (camera_stage.cpp),
/// carved from one aligned allocation.
struct Scratch {
    AlignedBytes all;
    float *row, *radiance, *zeros, *gain, *normal, *mean, *raw, *linear, *image, *tmp, *scale,
        *shown, *exact_mean, *exact_uniform, *exact_electrons, *exact_offset;
    std::int32_t *index, *flag;

    /// `whole_row`: also a row of 3 x width values (the lens map's radiance, the demosaic).
    Scratch(int width, bool whole_row) {
        constexpr std::size_t n = kChunk;
        const std::size_t f = line_bytes<float>(n), i = line_bytes<std::int32_t>(n),
                          r = whole_row ? line_bytes<float>(3 * std::size_t(width)) : 0;
        all = AlignedBytes(r + 15 * f + 2 * i);
        std::size_t at = 0;
        const auto take = [&](std::size_t bytes) {
            const std::size_t here = at;
            at += bytes;
            return here;
        };
        row = all.at<float>(take(r));
        for (float** p :
             {&radiance, &zeros, &gain, &normal, &mean, &raw, &linear, &image, &tmp, &scale, &shown,
              &exact_mean, &exact_uniform, &exact_electrons, &exact_offset})
            *p = all.at<float>(take(f));
        index = all.at<std::int32_t>(take(i));
        flag = all.at<std::int32_t>(take(i));
        std::memset(zeros, 0, f);
    }
    /// The per-channel scales of a frame, as a chunk.
    void scales(const float s[3]) {
        for (int u = 0; u < kChunk / 3; ++u)
            for (int c = 0; c < 3; ++c) scale[3 * u + c] = s[c];
    }
    RowBuffers rows(const float* rad, const float* response, const float* dsnu,
                    const std::int32_t* record) const {
        return {
            rad,    response, dsnu,       record,        normal,          mean,        flag, raw,
            linear, index,    exact_mean, exact_uniform, exact_electrons, exact_offset};
    }
};

/// n standard normal deviates of a stream from noise counter `base` on:
/// z[i] = normal_from_bits<float>(noise_bits(key, base + i)) (noise.h), vectorised with AVX2 and
/// FMA where the processor has them (there the table's polynomial is fused: the last bit may
/// differ from the generic code's). `index`: scratch for n ints. normal_row.cpp.
void normal_row(NoiseKey key, std::uint32_t base, int n, float* z, std::int32_t* index);

/// n values from noise counter `base` on (a chunk of a row): radiance to DN (docs/noise.md).
/// b.radiance must be 64-byte aligned unless reads_unaligned(p, b) (then it may lie anywhere).
void sensor_row(const SensorParams& p, std::uint32_t base, int n, const RowBuffers& b);

/// Whether the processor has AVX2 and FMA (sensor_avx2.cpp).
extern const bool kSensorAvx2;

/// The Gaussian path of sensor_row for the n values of a chunk with noise and no mosaic, with
/// AVX2 and FMA (only where kSensorAvx2): the bits of rows.cpp's x86-64-v3 clone; the radiance
/// read where it lies. Lists the values for the exact path in b.index and returns their number
/// (b.mean is written where a group of 8 has one of them, b.flag not at all).
int gaussian_values_avx2(const SensorParams& p, int n, const RowBuffers& b);

/// i % 3 for the values of a chunk (chunks start at whole pixels), kChunk of them, aligned.
const std::int32_t* chunk_channels();

/// Whether sensor_row reads b.radiance at any alignment for these parameters (no copy needed).
inline bool reads_unaligned(const SensorParams& p, bool mosaic) {
    return kSensorAvx2 && p.noise && !mosaic;
}

/// n values without noise, for the noise-free image: K min(mean, full well) + black, clipped to
/// the DN range, from the noise-free response (falloff x channel response, per millisecond).
void noise_free_row(const SensorParams& p, int n, const float* radiance, const float* response,
                    float* dn);

/// Each value's mean electrons per unit radiance for `pixels` pixels: the falloff at
/// x2[u] + y2 times resp[c].
void gain_row(const Vignetting& vig, const float* x2, float y2, const float resp[3], int pixels,
              float* gain);

/// The camera's fixed patterns for n values from noise counter `base` on (a row): PRNU scales
/// `response` by max(0, 1 + prnu z) (prnu 0: untouched), and `dsnu_out` (null: none) gets
/// dsnu z, each z a standard normal from its stream (normal_from_bits<float>).
void fixed_pattern_row(NoiseKey prnu_key, NoiseKey dsnu_key, std::uint32_t base, int n, float prnu,
                       float dsnu, float* response, float* dsnu_out);

/// Each of `pixels` pixels' bin in a histogram of the brightest raw DN, min(brightest, last),
/// from the pixels' raw DN (interleaved R, G, B: whole numbers >= 0).
void brightest_row(int pixels, const float* raw, std::int32_t last, std::int32_t* bin);

/// What the processing kernel needs (per-channel scales come as a row, `scale`).
struct ProcessParams {
    float black = 0;
    bool matrix = false;
    float m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    OutputCurve curve = OutputCurve::Linear;
    float inv_gamma = 1;
};

/// n DN values (whole pixels, interleaved) to display values: (dn - black) scale, the matrix,
/// clamp to [0, 1], the curve. `tmp` is scratch of the same size; out may be dn.
void process_row(const ProcessParams& p, int n, const float* scale, const float* dn, float* tmp,
                 float* out);

/// n whole DN values in [0, levels) (interleaved R, G, B) to display values through a table
/// `lut` of 3 x levels (entry 3 dn + c: channel c's display value of dn).
void lookup_row(const float* lut, int n, const float* dn, float* out);

/// lookup_row for a table of 8-bit codes (entry 3 dn + c; a 12-bit sensor's table is 12 KB): the
/// image as codes without display values in between.
void lookup_codes_row(const std::uint8_t* lut, int n, const float* dn, std::uint8_t* out);

#if defined(__x86_64__) && defined(__GNUC__)
/// out[j] = lut[at[j]] for the first `count` lanes of `at` (entries of a table of 8-bit codes),
/// by scalar loads: on the AMD EPYC of docs/camera-speed.md, vpgatherdd of the table took more
/// of the sensor loop's time than all its arithmetic.
__attribute__((target("avx2"), always_inline)) inline void read_codes(const std::uint8_t* lut,
                                                                      __m256i at, std::uint8_t* out,
                                                                      int count = 8) {
    alignas(32) std::int32_t k[8];
    _mm256_store_si256(reinterpret_cast<__m256i*>(k), at);
    for (int j = 0; j < count; ++j) out[j] = lut[k[j]];
}
#endif

}  // namespace deepsea::camera_rows
