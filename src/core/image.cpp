#include "deepsea/core/image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <utility>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {
thread_local const ExpectImageSize* t_expected = nullptr;
}  // namespace

ExpectImageSize::ExpectImageSize(int width, int height, std::string what)
    : m_width(width), m_height(height), m_what(std::move(what)), m_outer(t_expected) {
    t_expected = this;
}

ExpectImageSize::~ExpectImageSize() { t_expected = m_outer; }

void check_image_size(long long width, long long height, long long channels,
                      const std::string& what) {
    if (const ExpectImageSize* e = t_expected) {
        if (width != e->m_width || height != e->m_height) {
            throw InputError(e->m_what + ": sizes differ (" + std::to_string(width) + "x" +
                             std::to_string(height) + " vs " + std::to_string(e->m_width) + "x" +
                             std::to_string(e->m_height) + ")");
        }
    }
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    if (width < 1 || height < 1) throw InputError(what + ": image size " + size + " has no pixels");
    if (width > kMaxImageSide || height > kMaxImageSide ||
        (long double)width * height > kMaxImagePixels) {
        throw InputError(what + ": image size " + size + " is larger than deepsea's limit of " +
                         std::to_string(kMaxImagePixels / 1000000) + " megapixels (at most " +
                         std::to_string(kMaxImageSide) + " on a side)");
    }
    if (channels < 1 || channels > kMaxImageChannels) {
        throw InputError(what + ": " + std::to_string(channels) + " channels (deepsea reads 1 to " +
                         std::to_string(kMaxImageChannels) + ")");
    }
}

void require_same_size(const Image& a, const Image& b, const std::string& what) {
    require_same_size(a.width, a.height, b.width, b.height, what);
}

void require_same_size(int a_w, int a_h, int b_w, int b_h, const std::string& what) {
    if (a_w != b_w || a_h != b_h) {
        throw InputError(what + ": sizes differ (" + std::to_string(a_w) + "x" +
                         std::to_string(a_h) + " vs " + std::to_string(b_w) + "x" +
                         std::to_string(b_h) + ")");
    }
}

void throw_non_finite_color(const std::string& what, int u, int v, int channel, float value) {
    throw InputError(what + ": pixel (" + std::to_string(u) + ", " + std::to_string(v) + ") " +
                     "RGB"[channel] + " is " +
                     (std::isnan(value) ? "NaN"
                      : value > 0       ? "+inf"
                                        : "-inf") +
                     ": float colour is linear albedo and must be finite");
}

void require_finite_color(const Image& rgb, const std::string& what) {
    const std::size_t n = rgb.data.size();
    const std::size_t bad = tbb::parallel_reduce(
        tbb::blocked_range<std::size_t>(0, n, 1 << 16), n,
        [&](const tbb::blocked_range<std::size_t>& r, std::size_t first) {
            for (std::size_t i = r.begin(); i < r.end() && i < first; ++i)
                if (!std::isfinite(rgb.data[i])) return i;
            return first;
        },
        [](std::size_t a, std::size_t b) { return std::min(a, b); });
    if (bad == n) return;
    const std::size_t pixel = bad / 3;
    throw_non_finite_color(what, int(pixel % std::size_t(rgb.width)),
                           int(pixel / std::size_t(rgb.width)), int(bad % 3), rgb.data[bad]);
}

}  // namespace deepsea
