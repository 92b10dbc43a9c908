// The measurements behind docs/asset-format.md's accuracy tables: error of the asset lookup vs
// exact per-pixel integration over xy-step, K and depth scheme, for the authors' 800x800
// camera, two rigs and two waters. Disabled in CI (minutes of CPU); run it with
//   build/tests/bake_tests --gtest_also_run_disabled_tests --gtest_filter='*Sweep*'
// It is evaluate_asset_accuracy (what `deepsea bake --check` prints) with the exact reference
// computed once per rig x water and shared by every setting, on a coarser pixel stride.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/bake.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

const Camera kAuthors{800, 800, 600.0, 600.0, 400.0, 400.0};

/// volumes/rigs/authors-testset.yaml (baseline 0.5 m, yaw 0.536 rad) and paper-eval.yaml
/// (baseline 1 m, 45 degrees).
Rig yaml_rig(const char* name, double x, double dx, double dz) {
    Rig rig;
    rig.name = name;
    for (int s : {-1, 1}) {
        Light l;
        l.name = s < 0 ? "left" : "right";
        l.position = {x * s, 0.0, 0.0};
        l.direction = normalize(Vec3{-dx * s, 0.0, dz});
        l.intensity = {1.0, 1.0, 1.0};
        l.rid.sigma_deg = 35.0;
        rig.lights.push_back(l);
    }
    return rig;
}

template <typename F>
void parallel_rows(int n, F&& f) {
    const int workers = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> pool;
    for (int w = 0; w < workers; ++w) {
        pool.emplace_back([&, w] {
            for (int r = w; r < n; r += workers) f(r);
        });
    }
    for (auto& t : pool) t.join();
}

struct Reference {
    std::vector<int> us;
    std::vector<double> planes{2.0, 4.0, 8.0};
    std::vector<Rgb> exact;  ///< per pixel: planes..., then open water (to t_far)
    int scenes() const { return int(planes.size()) + 1; }
};

Reference make_reference(const Rig& rig, const Water& water, int stride, double tolerance) {
    Reference ref;
    for (int x = stride / 2; x < kAuthors.width; x += stride) ref.us.push_back(x);
    ref.us.push_back(kAuthors.width - 1);
    const int n = int(ref.us.size()), S = ref.scenes();
    ref.exact.resize(std::size_t(n) * n * S);
    const double t_far = far_path_length(water, tolerance);
    parallel_rows(n, [&](int jv) {
        for (int iu = 0; iu < n; ++iu) {
            const Vec3 ray = kAuthors.ray(ref.us[iu], ref.us[jv]);
            const double st = length(ray);
            std::vector<double> t{0.0};
            for (double z : ref.planes) t.push_back(z * st);
            t.push_back(std::max(t_far, t.back()));
            const auto C = backscatter_cumulative(rig, water, ray / st, t, {1e-8, 1e-16, 40});
            for (int s = 0; s < S; ++s) ref.exact[(std::size_t(jv) * n + iu) * S + s] = C[s + 1];
        }
    });
    return ref;
}

struct Score {
    std::vector<double> mean, max;
};

Score score(const Asset& a, const Reference& ref) {
    const int n = int(ref.us.size()), S = ref.scenes();
    Score sc{std::vector<double>(S, 0.0), std::vector<double>(S, 0.0)};
    for (int jv = 0; jv < n; ++jv) {
        for (int iu = 0; iu < n; ++iu) {
            for (int s = 0; s < S; ++s) {
                const double z = s < int(ref.planes.size()) ? ref.planes[s] : 1e30;
                const Rgb look = a.sample(ref.us[iu], ref.us[jv], z);
                const Rgb ex = ref.exact[(std::size_t(jv) * n + iu) * S + s];
                double e = 0.0;
                for (int c = 0; c < 3; ++c) e = std::max(e, std::abs(look[c] - ex[c]) / ex[c]);
                sc.mean[s] += e;
                sc.max[s] = std::max(sc.max[s], e);
            }
        }
    }
    for (double& m : sc.mean) m /= double(n) * n;
    return sc;
}

TEST(AccuracySweep, DISABLED_AuthorsCamera) {
    const fs::path dir = fs::temp_directory_path() / ("deepsea-sweep-" + std::to_string(getpid()));
    fs::create_directories(dir);
    const BakeSettings defaults;
    struct Case {
        int step, K;
        DepthScheme scheme;
    };
    std::vector<Case> cases;
    for (int step : {8, 16, 32, 64}) cases.push_back({step, 64, DepthScheme::Log});
    for (int K : {8, 16, 32, 128}) cases.push_back({16, K, DepthScheme::Log});
    for (int K : {16, 32, 64}) {
        for (DepthScheme s : {DepthScheme::Uniform, DepthScheme::Taylor, DepthScheme::Sqrt}) {
            cases.push_back({16, K, s});
        }
    }
    const int stride =
        std::getenv("DEEPSEA_SWEEP_STRIDE") ? std::atoi(std::getenv("DEEPSEA_SWEEP_STRIDE")) : 11;
    for (const char* rig_name : {"authors-testset", "paper-eval"}) {
        const Rig rig = rig_name[0] == 'a' ? yaml_rig(rig_name, 0.5, 0.510586, 0.859826)
                                           : yaml_rig(rig_name, 1.0, 0.707107, 0.707107);
        for (const char* wt : {"IB", "3C"}) {
            const Water water = jerlov_water(wt);
            const Reference ref = make_reference(rig, water, stride, defaults.tolerance);
            std::printf("\n%s, jerlov:%s (%zu^2 test pixels, stride %d)\n\n", rig_name, wt,
                        ref.us.size(), stride);
            std::printf(
                "| step | K | scheme | z_max m | MB | 2 m mean/max %% | 4 m | 8 m | "
                "open water |\n|---|---|---|---|---|---|---|---|---|\n");
            for (const Case& c : cases) {
                BakeSettings s;
                s.step = c.step;
                s.depth_samples = c.K;
                s.scheme = c.scheme;
                const Asset a = bake(kAuthors, rig, water, s);
                const std::string file = (dir / "a.vdb").string();
                write_asset(file, a);
                const double mb = fs::file_size(file) / 1e6;
                const Asset loaded = load_asset(file);  // half storage included
                const Score sc = score(loaded, ref);
                std::printf("| %d | %d | %s | %.2f | %.2f |", c.step, c.K, to_string(c.scheme),
                            a.lattice().z_max(), mb);
                for (std::size_t k = 0; k < sc.mean.size(); ++k) {
                    std::printf(" %.3f / %.3f |", 100 * sc.mean[k], 100 * sc.max[k]);
                }
                std::printf("\n");
                std::fflush(stdout);
            }
        }
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace deepsea
