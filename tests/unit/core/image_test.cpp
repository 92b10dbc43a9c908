#include "deepsea/core/image.h"

#include <gtest/gtest.h>

#include <limits>

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

namespace deepsea {

TEST(Image, NonFiniteColourIsAnInputErrorNamingTheFirstPixel) {
    Image rgb(7, 5, 3, 0.25f);
    EXPECT_NO_THROW(require_finite_color(rgb, "a.exr"));
    rgb.at(6, 4, 2) = -std::numeric_limits<float>::infinity();
    rgb.at(3, 2, 1) = std::numeric_limits<float>::quiet_NaN();
    try {
        require_finite_color(rgb, "a.exr");
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_STREQ(e.what(),
                     "a.exr: pixel (3, 2) G is NaN: float colour is linear albedo and must be "
                     "finite");
    }
    rgb.at(3, 2, 1) = 0.0f;
    EXPECT_THROW(require_finite_color(rgb, "a.exr"), InputError);  // the -inf alone
    // A large image: the first bad value wins whatever the split of the work.
    Image big(1000, 700, 3, 0.5f);
    big.at(999, 699, 0) = std::numeric_limits<float>::infinity();
    big.at(10, 400, 2) = std::numeric_limits<float>::infinity();
    try {
        require_finite_color(big, "b");
        FAIL() << "no exception";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("pixel (10, 400) B is +inf"), std::string::npos)
            << e.what();
    }
}

TEST(Image, AnExpectedSizeRefusesAnotherAtTheHeaderCheck) {
    EXPECT_NO_THROW(check_image_size(10000, 10000, 4, "big.png"));
    {
        const ExpectImageSize expect(32, 24, "c.png and d.exr");
        EXPECT_NO_THROW(check_image_size(32, 24, 3, "c.png"));
        try {
            check_image_size(10000, 10000, 4, "c.png");
            FAIL() << "no exception";
        } catch (const InputError& e) {
            EXPECT_STREQ(e.what(), "c.png and d.exr: sizes differ (10000x10000 vs 32x24)");
        }
        {
            const ExpectImageSize inner(8, 8, "inner");
            EXPECT_THROW(check_image_size(32, 24, 3, "c.png"), InputError);
        }
        EXPECT_NO_THROW(check_image_size(32, 24, 3, "c.png"));  // the outer one again
    }
    EXPECT_NO_THROW(check_image_size(10000, 10000, 4, "big.png"));  // none after the scope
}

}  // namespace deepsea
