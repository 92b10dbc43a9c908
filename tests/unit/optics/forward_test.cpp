// Transmission (transmission.h) and the forward-scatter weight (forward.h) by their
// properties, and their float instantiations (the runtime's rows) against double.

#include "deepsea/optics/forward.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "deepsea/optics/transmission.h"

namespace deepsea {

TEST(Transmission, IsBeerLambert) {
    const double c = 0.37;
    EXPECT_EQ(transmission(c, 0.0), 1.0);
    EXPECT_NEAR(transmission(c, 1.0 / c), std::exp(-1.0), 1e-15);  // one attenuation length
    // multiplicative over consecutive paths, 1 in clear water
    EXPECT_NEAR(transmission(c, 2.5 + 4.0), transmission(c, 2.5) * transmission(c, 4.0), 1e-15);
    EXPECT_EQ(transmission(0.0, 100.0), 1.0);
    const Rgb t = transmission(Rgb(0.1, 0.2, 0.4), 5.0);
    EXPECT_NEAR(t.r, std::exp(-0.5), 1e-15);
    EXPECT_NEAR(t.b, std::exp(-2.0), 1e-15);
}

TEST(ForwardWeight, ZeroWithoutForwardScatterAndAtTheCamera) {
    EXPECT_EQ(forward_weight(0.3, 0.3, 5.0), 0.0);  // G = c: nothing scattered forward
    EXPECT_EQ(forward_weight(0.1, 0.3, 0.0), 0.0);  // no water yet
    const double w = forward_weight(0.1, 0.3, 5.0);
    EXPECT_NEAR(w, std::exp(-0.5) - std::exp(-1.5), 1e-15);
    EXPECT_GT(w, 0.0);
    ForwardScatter fs;
    fs.G = {0.1, 0.2, 0.3};
    const Rgb wr = forward_weight(fs, Rgb(0.3, 0.3, 0.3), 5.0);
    EXPECT_EQ(wr.b, 0.0);
    EXPECT_NEAR(wr.r, w, 1e-15);
}

TEST(ForwardWeight, FloatMatchesDouble) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> coef(0.0, 1.0), dist(0.0, 15.0);
    for (int i = 0; i < 1000; ++i) {
        const double c = coef(rng), G = c * coef(rng), d = dist(rng);
        const double t = transmission(c, d);
        EXPECT_NEAR(transmission(float(c), float(d)), t, 1e-5 * t);
        // w is a difference: compare against the size of its terms
        EXPECT_NEAR(forward_weight(float(G), float(c), float(d)), forward_weight(G, c, d),
                    1e-5 * std::exp(-G * d));
    }
}

}  // namespace deepsea
