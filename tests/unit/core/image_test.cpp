#include "deepsea/core/image.h"

#include <gtest/gtest.h>

#include "deepsea/core/error.h"

namespace deepsea {

TEST(Image, IndexIsInterleavedRowMajor) {
    Image img(4, 3, 3);
    img.at(2, 1, 1) = 5.0f;
    EXPECT_EQ(img.data[(1 * 4 + 2) * 3 + 1], 5.0f);
    EXPECT_EQ(img.row(1)[2 * 3 + 1], 5.0f);
}

TEST(Image, SizeMismatchIsAnInputError) {
    Image a(4, 3, 3), b(4, 4, 1);
    EXPECT_THROW(require_same_size(a, b, "rgb vs depth"), InputError);
    EXPECT_NO_THROW(require_same_size(a, Image(4, 3, 1), "rgb vs depth"));
}

}  // namespace deepsea
