#include "deepsea/core/image.h"

#include "deepsea/core/error.h"

namespace deepsea {

void require_same_size(const Image& a, const Image& b, const std::string& what) {
    if (a.width != b.width || a.height != b.height) {
        throw InputError(what + ": sizes differ (" + std::to_string(a.width) + "x" +
                         std::to_string(a.height) + " vs " + std::to_string(b.width) + "x" +
                         std::to_string(b.height) + ")");
    }
}

}  // namespace deepsea
