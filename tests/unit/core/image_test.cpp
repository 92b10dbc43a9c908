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

TEST(Image, SizeLimitsAreStatedAndChecked) {
    EXPECT_NO_THROW(check_image_size(1, 1, 1, "a.png"));
    EXPECT_NO_THROW(check_image_size(10000, 10000, 3, "a.png"));  // exactly the limit
    for (long long side : {20000LL, 100000LL, 1LL << 40}) {
        try {
            check_image_size(side, side, 3, "big.png");
            FAIL() << side;
        } catch (const InputError& e) {
            EXPECT_EQ(std::string(e.what()).rfind("big.png: image size ", 0), 0u) << e.what();
            EXPECT_NE(std::string(e.what()).find("100 megapixels"), std::string::npos);
        }
    }
    EXPECT_THROW(check_image_size(200000, 1, 1, "a.png"), InputError);  // one side too long
    EXPECT_THROW(check_image_size(0, 5, 1, "a.png"), InputError);
    EXPECT_THROW(check_image_size(5, 5, 0, "a.png"), InputError);
    EXPECT_THROW(check_image_size(5, 5, kMaxImageChannels + 1, "a.png"), InputError);
}

}  // namespace deepsea
