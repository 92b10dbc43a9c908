// The baker's stated limits and stops (issue 29): z_max and path counts have ranges, a lattice
// OpenVDB cannot store is refused before any column, no OpenVDB exception reaches a caller
// raw, every stage of a bake (the exact columns, the Monte Carlo columns, the lamp tables)
// stops within a fraction of a second of its StopFlag, and one ray's quadrature is bounded.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <thread>

#include "bake_fixtures.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/bake.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/lamp_field.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Runs f, sets `stop` after `delay` s from another thread, and returns how long f went on
/// after that; f must throw Cancelled (a failure otherwise).
template <class F>
double seconds_to_stop(StopFlag& stop, double delay, const F& f) {
    std::atomic<bool> done{false};
    std::chrono::steady_clock::time_point set_at{};
    std::thread setter([&] {
        const auto t0 = std::chrono::steady_clock::now();
        while (!done && seconds_since(t0) < delay)
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        set_at = std::chrono::steady_clock::now();
        stop = SIGTERM;
    });
    bool cancelled = false;
    try {
        f();
    } catch (const Cancelled&) {
        cancelled = true;
    }
    const auto end = std::chrono::steady_clock::now();
    done = true;
    setter.join();
    EXPECT_TRUE(cancelled) << "finished before the stop (make the work longer)";
    return std::chrono::duration<double>(end - set_at).count();
}

/// seconds_to_stop for a bake of the two lamps in Jerlov IB with settings s, without the
/// bake's own check, on two threads.
double bake_stops_after(BakeSettings s, double delay) {
    s.check = false;
    StopFlag stop{0};
    return seconds_to_stop(stop, delay, [&] {
        bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s,
             Parallel{2}.with_stop(&stop));
    });
}

TEST(BakeLimits, ZMaxHasARange) {
    const auto rejects = [](double z) {
        BakeSettings s;
        s.z_max = z;
        try {
            validate(s);
            ADD_FAILURE() << "accepted z_max " << z;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find("z_max must be in [0.01, 1000] metres"),
                      std::string::npos)
                << e.what();
        }
    };
    for (double z : {1e-300, 1e-3, 0.0099, 1000.5, 1e6, -1.0, std::nan(""), HUGE_VAL}) rejects(z);
    for (double z : {0.0 /* auto */, kMinZMax, 1.0, kMaxZMax}) {
        BakeSettings s;
        s.z_max = z;
        EXPECT_NO_THROW(validate(s)) << z;
    }
}

TEST(BakeLimits, PathsAndLampSamplesHaveAnUpperBound) {
    BakeSettings s;
    s.higher_orders.paths = 2147483647;
    EXPECT_THROW(validate(s), ConfigError);  // single scattering too: a library checks once
    s.scattering = Scattering::Multiple;
    try {
        validate(s);
        ADD_FAILURE();
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("paths must be in [1, 4194304]"), std::string::npos)
            << e.what();
    }
    s.higher_orders.paths = kMaxPaths;
    EXPECT_NO_THROW(validate(s));
    s.higher_orders.lamp_samples = kMaxLampSamples + 1;
    EXPECT_THROW(validate(s), ConfigError);
    EXPECT_EQ(kMaxPaths, 64 * HigherOrderSettings{}.paths);
    EXPECT_EQ(kMaxLampSamples, 64 * HigherOrderSettings{}.lamp_samples);
}

TEST(BakeLimits, ALatticeOpenVdbCannotStoreIsRefusedBeforeAnyColumn) {
    // A narrow camera (0.04 degrees across), 1 cm deep, 4096 samples: cells of 0.4 x 0.6 x 2.4
    // micrometres, below OpenVDB's smallest transform.
    const Camera tele{64, 48, 1e5, 1e5, 31.5, 23.5};
    BakeSettings s = test::small_bake_settings();
    s.z_max = kMinZMax;
    s.depth_samples = kMaxDepthSamples;
    s.check = false;
    long calls = 0;
    const Parallel par{0, 0, [&](long, long) { return ++calls > 0; }};
    try {
        bake(tele, test::two_lamp_rig(), jerlov_water("IB"), s, par);
        ADD_FAILURE() << "baked an unstorable lattice";
    } catch (const ConfigError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("cannot be stored"), std::string::npos) << what;
        EXPECT_NE(what.find("too small for an OpenVDB transform"), std::string::npos) << what;
    }
    EXPECT_EQ(calls, 0);  // no column was computed

    // Writing such an asset anyway is an AssetError naming the cells, not OpenVDB's
    // ArithmeticError.
    Asset a;
    a.info.camera = tele;
    a.info.rig = test::two_lamp_rig();
    a.info.water = jerlov_water("IB");
    a.info.lattice = make_lattice(tele, 8, DepthScheme::Uniform,
                                  depth_samples(DepthScheme::Uniform, kMaxDepthSamples, kMinZMax));
    a.info.baker_version = "test";
    a.info.input_hash = "fnv1a64:0000000000000000";
    a.allocate();
    const fs::path dir =
        fs::temp_directory_path() / ("deepsea-bake-limits-" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string path = (dir / "tiny.vdb").string();
    try {
        write_asset(path, a);
        ADD_FAILURE() << "wrote an unstorable lattice";
    } catch (const AssetError& e) {
        EXPECT_NE(std::string(e.what()).find("too small for an OpenVDB transform"),
                  std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
    fs::remove_all(dir);
}

TEST(BakeLimits, AStopSetBeforehandComputesNothing) {
    StopFlag stop{SIGINT};
    long calls = 0;
    Parallel par{0, 0, [&](long, long) { return ++calls > 0; }};
    EXPECT_THROW(bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"),
                      test::small_bake_settings(), par.with_stop(&stop)),
                 Cancelled);
    EXPECT_EQ(calls, 0);
}

TEST(BakeLimits, TheExactStageStopsWithinASecond) {
    // One column of a 1 px lattice is a few milliseconds; a whole grain of 16 of them with the
    // strictest quadrature is longer. The stop must land well within a second either way.
    BakeSettings s = test::small_bake_settings();
    s.step = 1;
    s.depth_samples = 256;
    s.quadrature = Quadrature{kMinRelTol, 0.0, kMaxQuadratureDepth};
    const double after = bake_stops_after(s, 0.3);
    std::printf("exact stage: stopped %.3f s after the flag\n", after);
    EXPECT_LT(after, 0.5);
}

TEST(BakeLimits, TheMonteCarloStagesStopWithinASecond) {
    // With the most paths, one Monte Carlo column takes minutes: the stop must reach inside it,
    // with no progress callback at all (the CLI's signal flag alone).
    BakeSettings s = test::small_bake_settings();
    s.scattering = Scattering::Multiple;
    s.higher_orders.paths = kMaxPaths;
    const double after = bake_stops_after(s, 0.5);
    std::printf("Monte Carlo stage: stopped %.3f s after the flag\n", after);
    EXPECT_LT(after, 0.5);
    // The lamp tables (the stage after it) as well: many samples per node.
    LampFieldSettings ls;
    ls.samples = kMaxLampSamples;
    StopFlag stop2{0};
    const double after2 = seconds_to_stop(stop2, 0.3, [&] {
        bake_lamp_field(test::two_lamp_rig().lights[0], jerlov_water("IB"), ls,
                        Parallel{2}.with_stop(&stop2));
    });
    std::printf("lamp tables: stopped %.3f s after the flag\n", after2);
    EXPECT_LT(after2, 0.5);
}

TEST(BakeLimits, OneRaysQuadratureIsBounded) {
    // The strictest accepted tolerance and depth on a ray passing 2 cm from a lamp, 200 m
    // long: the bisection went on toward 2^60 panels around the lamp's peak. Bounded, it still
    // gives the integral (the greedy pass puts the panels where the error is; the depth-first
    // bisection alone, cut at the bound, was 13 % off).
    Rig rig = test::two_lamp_rig();
    rig.lights[0].position = {0.05, 0.02, 1.0};
    const Vec3 dir = normalize(Vec3{0.05, 0.0, 1.0});
    std::vector<double> t;
    for (int k = 0; k <= 64; ++k) t.push_back(200.0 * k / 64);
    const Quadrature strict{kMinRelTol, 0.0, kMaxQuadratureDepth};
    // This thread's CPU time, not the wall clock: a machine loaded by other work (or a
    // sanitizer build, 2-3x slower) must not fail it. Unbounded, the bisection never ends;
    // bounded it takes about 0.3 s of CPU in a release build.
    const auto cpu_seconds = [] {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
    };
    const double t0 = cpu_seconds();
    const std::vector<Rgb> C = backscatter_cumulative(rig, jerlov_water("IB"), dir, t, strict);
    const double took = cpu_seconds() - t0;
    std::printf("strict grazing ray: %.3f s of CPU\n", took);
    EXPECT_LT(took, 10.0);
    // The reference: 1 mm pieces over the lamp's peak (t near 1 m), each its own integral.
    Rgb ref = backscatter_integral(rig, jerlov_water("IB"), dir, 0.0, 0.5, strict).value +
              backscatter_integral(rig, jerlov_water("IB"), dir, 1.5, 200.0, strict).value;
    for (int i = 0; i < 1000; ++i) {
        ref += backscatter_integral(rig, jerlov_water("IB"), dir, 0.5 + 1e-3 * i,
                                    0.5 + 1e-3 * (i + 1), strict)
                   .value;
    }
    const std::vector<Rgb> bake_q =
        backscatter_cumulative(rig, jerlov_water("IB"), dir, t, BakeSettings{}.quadrature);
    for (int c = 0; c < 3; ++c) {
        std::printf("channel %d: strict %.9g, the bake's quadrature %.9g, reference %.9g\n", c,
                    C.back()[c], bake_q.back()[c], ref[c]);
        EXPECT_TRUE(std::isfinite(C.back()[c]));
        EXPECT_NEAR(C.back()[c], ref[c], 1e-4 * ref[c]);
    }
}

}  // namespace
}  // namespace deepsea
