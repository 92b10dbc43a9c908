#include "deepsea/optics/water.h"

#include <algorithm>
#include <cmath>

namespace deepsea {

namespace {
/// Half-angle of the cone whose scattered light stays close to the image point it came from.
constexpr double kForwardCone = 5.0 * M_PI / 180.0;
}  // namespace

ForwardScatter default_forward_scatter(const Water& water) {
    // Light scattered by less than the cone angle still arrives near its image point, so it
    // is not lost: it decays with G = c - f b instead of c (f = the phase function's fraction
    // within the cone). Its angular spread grows with the number of such events per metre,
    // f b, each deflecting by the cone's rms angle, seen on average from mid-path (1/sqrt 3).
    // docs/model.md has the derivation; G <= c holds by construction.
    const double f = water.phase.fraction_within(kForwardCone);
    // rms angle of the scattering inside the cone
    const double psi2 = [&] {
        double num = 0.0, den = 0.0;
        const int n = 2000;
        for (int i = 1; i <= n; ++i) {
            const double psi = kForwardCone * (i - 0.5) / n;
            const double w = water.phase(std::cos(psi)) * std::sin(psi);
            num += w * psi * psi;
            den += w;
        }
        return den > 0.0 ? num / den : 0.0;
    }();
    ForwardScatter fs;
    fs.enabled = true;
    for (int ch = 0; ch < 3; ++ch) fs.G[ch] = std::max(0.0, water.c[ch] - f * water.b[ch]);
    fs.k = f * water.b.g * std::sqrt(psi2) / std::sqrt(3.0);
    return fs;
}

}  // namespace deepsea
