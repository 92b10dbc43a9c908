#include "deepsea/core/image.h"

#include "deepsea/core/error.h"

namespace deepsea {

void check_image_size(long long width, long long height, long long channels,
                      const std::string& what) {
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

}  // namespace deepsea
