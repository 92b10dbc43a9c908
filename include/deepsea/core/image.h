#pragma once
/// \file Interleaved float images, the one pixel container of the library.

#include <cstddef>
#include <string>
#include <vector>

namespace deepsea {

/// Largest image deepsea reads, renders or configures: 100 million pixels (10000 x 10000, or
/// 12 x a 4K frame), at most kMaxImageSide on a side and kMaxImageChannels channels. A file
/// header claiming more is refused before anything is allocated.
inline constexpr long long kMaxImagePixels = 100'000'000;
inline constexpr long long kMaxImageSide = 100'000;
inline constexpr int kMaxImageChannels = 64;

/// InputError "`what`: ..." unless width x height (x channels) is a size deepsea accepts: both
/// sides >= 1 and within the limits above. `what` names the file (or setting).
void check_image_size(long long width, long long height, long long channels,
                      const std::string& what);

/// InputError "`what`: pixel (u, v) G is NaN: ..." naming the first non-finite value (row by
/// row) of a linear RGB colour image. Float colour is linear albedo: one NaN or infinity would
/// spread through the forward scatter to every pixel of the frame and end the automatic
/// exposure, so float colour from files and arrays is checked where it enters.
struct Image;
void require_finite_color(const Image& rgb, const std::string& what);
/// That error for sample `channel` (0 R, 1 G, 2 B) of pixel (u, v), holding `value`.
[[noreturn]] void throw_non_finite_color(const std::string& what, int u, int v, int channel,
                                         float value);

/// While one is alive, check_image_size on this thread (every decoder calls it on the header,
/// before allocating) also refuses a size other than width x height, with require_same_size's
/// message for `what`: a colour file is checked against its depth before it is decoded (a
/// 777 KB PNG can hold 10000 x 10000 16-bit RGBA, 1.4 GB decoded). Scopes nest.
class ExpectImageSize {
public:
    ExpectImageSize(int width, int height, std::string what);
    ~ExpectImageSize();
    ExpectImageSize(const ExpectImageSize&) = delete;
    ExpectImageSize& operator=(const ExpectImageSize&) = delete;

private:
    friend void check_image_size(long long, long long, long long, const std::string&);
    int m_width, m_height;
    std::string m_what;
    const ExpectImageSize* m_outer;
};

/// A width x height image of `channels` interleaved floats per pixel, rows top to bottom.
/// Colour is linear RGB; depth is one channel in metres.
struct Image {
    int width = 0;
    int height = 0;
    int channels = 0;
    std::vector<float> data;

    Image() = default;
    Image(int w, int h, int c, float fill = 0.0f)
        : width(w), height(h), channels(c), data(std::size_t(w) * h * c, fill) {}

    bool empty() const { return data.empty(); }
    std::size_t index(int x, int y, int c = 0) const {
        return (std::size_t(y) * width + x) * channels + c;
    }
    float& at(int x, int y, int c = 0) { return data[index(x, y, c)]; }
    float at(int x, int y, int c = 0) const { return data[index(x, y, c)]; }
    float* row(int y) { return data.data() + std::size_t(y) * width * channels; }
    const float* row(int y) const { return data.data() + std::size_t(y) * width * channels; }
};

/// Throws InputError naming `what` unless a and b have the same width and height.
void require_same_size(const Image& a, const Image& b, const std::string& what);
/// The same for sizes given as numbers (a_w x a_h against b_w x b_h).
void require_same_size(int a_w, int a_h, int b_w, int b_h, const std::string& what);

}  // namespace deepsea
