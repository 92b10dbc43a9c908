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
    if (a.width != b.width || a.height != b.height) {
        throw InputError(what + ": sizes differ (" + std::to_string(a.width) + "x" +
                         std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                         std::to_string(b.height) + ")");
    }
}

}  // namespace deepsea
