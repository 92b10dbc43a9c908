#include "deepsea/optics/lamp_field.h"

#include <algorithm>

#include "deepsea/core/error.h"
#include "deepsea/core/random.h"
#include "deepsea/optics/multiple_scattering.h"

namespace deepsea {

void lamp_frame(const Vec3& a, Vec3& x, Vec3& y) {
    // Any perpendicular pair: the field is symmetric about the axis.
    x = rotate_about(a, 0.0, 0.0);
    y = cross(a, x);
}

LampField bake_lamp_field(const Light& lamp, const Water& water, const LampFieldSettings& s,
                          const Parallel& par) {
    if (s.nr < 2 || s.ntheta < 2 || !(s.r0 > 0.0) || !(s.r_max > s.r0) || s.samples < 1) {
        throw ConfigError("lamp field: needs nr, ntheta >= 2, 0 < r0 < r_max, samples >= 1");
    }
    Light local = lamp;
    local.position = Vec3();
    local.direction = Vec3(0, 0, 1);
    local.intensity = Rgb(1.0);
    const Transport tr(Rig{"lamp", {local}}, water);
    LampField f;
    f.nr = s.nr;
    f.ntheta = s.ntheta;
    f.r0 = s.r0;
    f.r_max = s.r_max;
    f.sh.assign(f.size(), 0.0f);
    std::vector<double> rel(std::size_t(s.nr) * s.ntheta, 0.0);
    const double log_step = std::log(s.r_max / s.r0) / (s.nr - 1);
    parallel_for(
        std::size_t(s.nr) * s.ntheta,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t n = begin; n < end; ++n) {
                const int i = int(n) / s.ntheta, j = int(n) % s.ntheta;
                const double r = s.r0 * std::exp(log_step * i);
                const double theta = M_PI * j / (s.ntheta - 1);
                const Vec3 X(r * std::sin(theta), 0.0, r * std::cos(theta));
                Rng rng(mix_seed(s.seed, n, 0x6c616d70));
                const ShEstimate e = scattered_radiance_sh(tr, X, s.samples, rng, par.stop);
                float* out = f.sh.data() + n * kShCount * 3;
                for (int k = 0; k < kShCount * 3; ++k) out[k] = float(e.value[k]);
                if (s.symmetric)
                    for (int m : {1, 4, 5}) std::fill(out + 3 * m, out + 3 * m + 3, 0.0f);
                // Error of the irradiance facing the lamp (n = -X / r), green channel.
                double Y[kShCount], E = 0.0, var = 0.0;
                sh_basis(-X.x / r, -X.y / r, -X.z / r, Y);
                for (int m = 0; m < kShCount; ++m) {
                    const double a = sh_cosine_factor<double>(m) * Y[m];
                    E += a * e.value[3 * m + 1];
                    var += a * a * e.std_error[3 * m + 1] * e.std_error[3 * m + 1];
                }
                rel[n] = E > 0.0 ? std::sqrt(var) / E : 0.0;
            }
        },
        par.or_grain(4));
    for (double x : rel) f.rel_std_error += x / double(rel.size());
    return f;
}

}  // namespace deepsea
