#pragma once
// Internal to the runtime: three colour planes of one resolution and the separable Gaussian
// blur, row interpolation and upsampling the forward-scatter blurs share.

#include <cstddef>
#include <vector>

#include "deepsea/core/image.h"

namespace deepsea::planes {

/// Three colour planes of one resolution, read with strides: an interleaved image (no planar
/// copy) or planar data.
struct Source {
    const float* data = nullptr;
    int w = 0, h = 0;
    std::size_t channel = 0, pixel = 1, row = 0;  ///< strides in floats
    const float* at(int c, int y) const { return data + c * channel + std::size_t(y) * row; }
    float operator()(int c, int x, int y) const { return at(c, y)[x * pixel]; }
};

Source interleaved(const Image& in);
Source planar(const float* data, int w, int h);

/// Whether a result replaces what its destination holds or is added to it.
enum class Store { Set, Add };

/// What lies beyond the image: its own mean under the kernel (normalised over in-image taps),
/// or its border pixels continued outward. Both keep a uniform image uniform; where the image
/// is brighter inside than at its borders (lamp-lit scenes), Normalise moves the inside's light
/// to the borders, Clamp keeps the borders' own.
enum class Edge { Normalise, Clamp };

/// With Edge::Clamp: the border pixels continued outward, each times its own factor at each
/// distance, so that a lamp-lit scene can dim beyond the frame as its light does. Per plane c:
/// left[(c * h + y) * reach + k - 1] is pixel (-k, y) over pixel (0, y), right the same beyond
/// column w - 1, top[(c * reach + k - 1) * w + x] pixel (x, -k) over (x, 0) (applied to the
/// horizontal pass's row 0), bottom beyond row h - 1; k = 1 .. reach, reach >= radius(sigma).
struct Fade {
    int reach = 0;
    const float* left = nullptr;
    const float* right = nullptr;
    const float* top = nullptr;
    const float* bottom = nullptr;
};

/// The kernel's radius in pixels for `sigma`: the taps blur_planes takes on each side.
int radius(double sigma);

/// Separable Gaussian of `sigma` (pixels of this resolution) of 3 planes, src to planar dst
/// (stored or added), with `edge` beyond the image. g, nx, ny (kernel, row and column
/// normalisation) are the caller's, kept between frames so that nothing is allocated once they
/// have grown (each worker keeps its own few rows of the horizontal pass). `fade` (Clamp only,
/// may be null: the borders unchanged) dims the continued borders.
void blur_planes(const Source& src, float* dst_planes, double sigma, std::vector<float>& g,
                 std::vector<float>& nx, std::vector<float>& ny, Store store = Store::Set,
                 Edge edge = Edge::Normalise, const Fade* fade = nullptr);

/// A Gaussian (pixels) narrower than this has taps beside the centre holding at most 1e-9 of
/// its weight (2 exp(-1 / (2 sigma^2)) <= 8e-10 at 0.152): blurring by it changes a value by at
/// most 1e-9 of the image's maximum (each pass moves at most its side taps' share of the largest
/// neighbour), below a float's resolution of 6e-8, so the blur can be left out.
inline constexpr double kIdentitySigma = 0.152;

/// dst[i] += src[i], n floats (an unblurred plane added where blur_planes would add its blur).
void add_planes(std::size_t n, const float* src, float* dst);

/// dst = a + t (b - a), n floats.
void lerp_rows(int n, const float* a, const float* b, float t, float* dst);

/// acc[u] += w[u] * (bilinear sample of the low-resolution row at x0[u] .. x1[u]).
void add_upsampled(int n, const float* w, const float* row, const int* x0, const int* x1,
                   const float* ax, float* acc);

/// acc[u] += w[u] * (bilinear sample at full-resolution row v of a w_lo x h_lo plane q that is
/// the image downsampled by `factor`; x0, x1, ax: its horizontal taps per output column).
/// tmp holds w_lo floats.
void add_upsampled_row(int n, int v, int factor, const float* q, int w_lo, int h_lo, const int* x0,
                       const int* x1, const float* ax, const float* w, float* tmp, float* acc);

}  // namespace deepsea::planes
