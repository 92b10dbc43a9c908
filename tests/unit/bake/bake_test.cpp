// The baker: its values are optics' exact integrals, bit-identical at any thread count, its
// auto z_max keeps its promise, bad settings are refused, and a baked asset survives the file.
// Small cameras (64x48) keep the whole binary well under a few seconds.

#include "deepsea/bake/bake.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "../temp_folder.h"
#include "bake_fixtures.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/bake/accuracy.h"
#include "deepsea/bake/higher_orders.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

namespace fs = std::filesystem;

TEST(Bake, ValuesAreTheExactCumulativeIntegrals) {
    const Rig rig = test::two_lamp_rig();
    const Water water = jerlov_water("IB");
    for (DepthScheme scheme : {DepthScheme::Uniform, DepthScheme::Log, DepthScheme::Taylor}) {
        BakeSettings s = test::small_bake_settings();
        s.scheme = scheme;
        const Asset a = bake(test::kBakeCam, rig, water, s);
        const Lattice& l = a.lattice();
        ASSERT_EQ(l.ni, lattice_count(64, 8));
        ASSERT_EQ(l.nj, lattice_count(48, 8));
        ASSERT_EQ(l.slabs(), 12);
        ASSERT_EQ(a.values.size(), std::size_t(3 * l.ni * l.nj * l.nk()));
        // Corners, the centre and an odd column: t = z |r| along the unit ray.
        for (auto [i, j] : {std::pair{0, 0}, {l.ni - 1, l.nj - 1}, {4, 3}, {1, 5}}) {
            const Vec3 ray = test::kBakeCam.ray(l.u(i), l.v(j));
            std::vector<double> t;
            for (double z : l.z) t.push_back(z * length(ray));
            const auto C = backscatter_cumulative(rig, water, ray / length(ray), t, s.quadrature);
            for (int k = 0; k < l.nk(); ++k) {
                for (int c = 0; c < 3; ++c) {
                    EXPECT_FLOAT_EQ(a.at(i, j, k)[c], float(C[k][c]))
                        << to_string(scheme) << " column " << i << "," << j << " k " << k;
                }
            }
            EXPECT_EQ(a.at(i, j, 0)[0], 0.0f);
            for (int k = 1; k < l.nk(); ++k) EXPECT_GE(a.at(i, j, k).g, a.at(i, j, k - 1).g);
        }
    }
}

TEST(Bake, BitIdenticalAtOneAndTwoThreads) {
    BakeSettings s = test::small_bake_settings();
    s.z_max = 0.0;  // auto: the z_max search is parallel too
    const Asset a1 = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("3C"), s, {1});
    const Asset a2 = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("3C"), s, {2});
    ASSERT_EQ(a1.values.size(), a2.values.size());
    EXPECT_EQ(a1.lattice().z, a2.lattice().z);
    EXPECT_EQ(0, std::memcmp(a1.values.data(), a2.values.data(), a1.values.size() * sizeof(float)));
    EXPECT_EQ(a1.info.input_hash, a2.info.input_hash);
}

TEST(Bake, ProgressReachesTheTotal) {
    BakeSettings s = test::small_bake_settings();
    long last = 0, total = 0, calls = 0;
    const Parallel par{0, 0, [&](long done, long t) {
                           EXPECT_GT(done, last);  // serialised and increasing
                           last = done;
                           total = t;
                           ++calls;
                           return true;
                       }};
    const Asset a = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s, par);
    EXPECT_GT(calls, 0);
    EXPECT_EQ(last, a.lattice().columns());
    EXPECT_EQ(total, a.lattice().columns());
    // With an auto z_max the search comes first, on the same bar: twice the columns.
    s.z_max = 0.0;
    last = 0;
    const Asset b = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s, par);
    EXPECT_EQ(last, 2 * b.lattice().columns());
    EXPECT_EQ(total, 2 * b.lattice().columns());
}

TEST(Bake, ProgressCanCancel) {
    long last = 0;
    const Parallel par{2, 1, [&](long done, long) {
                           last = done;
                           return done < 3;
                       }};
    EXPECT_THROW(bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"),
                      test::small_bake_settings(), par),
                 Cancelled);
    EXPECT_GE(last, 3);
    EXPECT_LT(last, bake_request(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"),
                                 test::small_bake_settings())
                        .lattice.columns());
}

TEST(Bake, AutoZMaxMeetsItsTolerance) {
    const Rig rig = test::two_lamp_rig();
    const Water water = jerlov_water("IB");
    const double tol = 1e-3;
    const double z_max = auto_z_max(test::kBakeCam, rig, water, 8, tol);
    ASSERT_GT(z_max, 0.5);
    ASSERT_LT(z_max, 100.0);
    const double t_far = far_path_length(water, tol);
    double worst = 0.0, worst_before = 0.0;
    for (int i = 0; i < lattice_count(64, 8); ++i) {
        for (int j = 0; j < lattice_count(48, 8); ++j) {
            const Vec3 ray = test::kBakeCam.ray(i * 8.0, j * 8.0);
            const double st = length(ray);
            // The tail beyond z_max, and beyond a depth 10 % shorter (which must miss it
            // somewhere, or the search was needlessly deep).
            const auto C = backscatter_cumulative(rig, water, ray / st,
                                                  {0.0, 0.9 * z_max * st, z_max * st, t_far},
                                                  {1e-7, 1e-15, 40});
            for (int c = 0; c < 3; ++c) {
                worst = std::max(worst, (C[3][c] - C[2][c]) / C[3][c]);
                worst_before = std::max(worst_before, (C[3][c] - C[1][c]) / C[3][c]);
            }
        }
    }
    EXPECT_LE(worst, tol);
    EXPECT_GT(worst_before, tol);

    // bake() with z_max = auto uses that depth and records the request, not the result.
    BakeSettings s = test::small_bake_settings();
    s.z_max = 0.0;
    s.tolerance = tol;
    const Asset a = bake(test::kBakeCam, rig, water, s);
    EXPECT_DOUBLE_EQ(a.lattice().z_max(), z_max);
    EXPECT_TRUE(a.info.z_max_auto);
    EXPECT_EQ(a.info.tolerance, tol);
}

TEST(Bake, RequestHashMatchesTheBakedAsset) {
    const Rig rig = test::two_lamp_rig();
    const Water water = jerlov_water("IB");
    for (double z_max : {0.0, 6.0}) {  // auto and fixed
        BakeSettings s = test::small_bake_settings();
        s.z_max = z_max;
        const BakeInfo want = bake_request(test::kBakeCam, rig, water, s);
        const Asset a = bake(test::kBakeCam, rig, water, s);
        EXPECT_EQ(want.input_hash, a.info.input_hash) << "z_max " << z_max;
        EXPECT_EQ(input_hash(a.info), a.info.input_hash);
        // Any setting is an input (threads and progress are not settings but a Parallel).
        s.depth_samples += 1;
        EXPECT_NE(bake_request(test::kBakeCam, rig, water, s).input_hash, want.input_hash);
    }
    BakeSettings s = test::small_bake_settings();
    const std::string h = bake_request(test::kBakeCam, rig, water, s).input_hash;
    s.step = 4;
    EXPECT_NE(bake_request(test::kBakeCam, rig, water, s).input_hash, h);
    s = test::small_bake_settings();
    s.z_max = 0.0;
    const std::string h_auto = bake_request(test::kBakeCam, rig, water, s).input_hash;
    s.tolerance = 1e-3;
    EXPECT_NE(bake_request(test::kBakeCam, rig, water, s).input_hash, h_auto);
    EXPECT_NE(bake_request(test::kBakeCam, rig, jerlov_water("3C"), test::small_bake_settings())
                  .input_hash,
              h);
}

TEST(Bake, ValidateRejectsBadSettings) {
    EXPECT_NO_THROW(validate(BakeSettings{}));
    auto rejects = [](auto change, const char* word) {
        BakeSettings s;
        change(s);
        try {
            validate(s);
            ADD_FAILURE() << "accepted a bad setting: " << word;
        } catch (const ConfigError& e) {
            EXPECT_NE(std::string(e.what()).find(word), std::string::npos) << e.what();
        }
    };
    rejects([](BakeSettings& s) { s.depth_samples = 1; }, "depth_samples");
    rejects([](BakeSettings& s) { s.depth_samples = -1; }, "depth_samples");  // 0 is auto
    rejects([](BakeSettings& s) { s.z_max = -1.0; }, "z_max");
    rejects([](BakeSettings& s) { s.z_max = std::nan(""); }, "z_max");
    rejects([](BakeSettings& s) { s.step = -1; }, "xy_step");  // 0 is auto
    rejects(
        [](BakeSettings& s) {
            s.check = false;
            s.strict = true;
        },
        "strict");
    rejects([](BakeSettings& s) { s.tolerance = 0.0; }, "tolerance");
    rejects([](BakeSettings& s) { s.tolerance = 0.5; }, "tolerance");
    // bake() validates too, and refuses a rig without lamps.
    BakeSettings s = test::small_bake_settings();
    s.depth_samples = 1;
    EXPECT_THROW(bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s), ConfigError);
    EXPECT_THROW(bake(test::kBakeCam, Rig{}, jerlov_water("IB"), test::small_bake_settings()),
                 ConfigError);
    try {
        bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), test::small_bake_settings(),
             {-1});
        ADD_FAILURE() << "accepted threads = -1";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find("threads"), std::string::npos) << e.what();
    }
}

class BakeFile : public test::TempFolderTest {};

TEST_F(BakeFile, RoundTripSamplesMatch) {
    BakeSettings s = test::small_bake_settings();
    s.scheme = DepthScheme::Log;
    const Asset a = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s);
    for (bool half : {false, true}) {
        WriteOptions opt;
        opt.half = half;
        opt.preview = half;  // one of each
        write_asset(path("a.vdb"), a, opt);
        const Asset b = load_asset(path("a.vdb"));
        EXPECT_EQ(b.info.input_hash, a.info.input_hash);
        EXPECT_EQ(b.lattice(), a.lattice());
        // Half floats keep 11 significant bits: 2^-11 relative.
        const double tol = half ? 1.0 / 2048 : 0.0;
        for (double u : {0.0, 13.3, 31.5, 63.0}) {
            for (double v : {0.0, 7.7, 47.0}) {
                for (double z : {0.3, 2.0, 4.5, 6.0, 1e9}) {
                    const Rgb x = a.sample(u, v, z), y = b.sample(u, v, z);
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_NEAR(y[c], x[c], tol * x[c]) << u << "," << v << "," << z;
                    }
                }
            }
        }
    }
}

TEST_F(BakeFile, FailedWriteLeavesNoFile) {
    const Asset a =
        bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), test::small_bake_settings());
    const std::string missing = path("no/such/dir/a.vdb");
    EXPECT_THROW(require_writable(missing), IoError);
    EXPECT_THROW(write_asset(missing, a), IoError);
    EXPECT_FALSE(fs::exists(path("no")));
    // An inconsistent asset is refused before anything is written, and an existing file of
    // the same name survives untouched.
    write_asset(path("a.vdb"), a);
    const auto size = fs::file_size(path("a.vdb"));
    Asset broken = a;
    broken.values.pop_back();
    EXPECT_THROW(write_asset(path("a.vdb"), broken), AssetError);
    EXPECT_EQ(fs::file_size(path("a.vdb")), size);
    EXPECT_NO_THROW(load_asset(path("a.vdb")));
    int files = 0;
    for (const auto& e : fs::directory_iterator(dir_)) {
        (void)e;
        ++files;
    }
    EXPECT_EQ(files, 1);  // no temporary left behind
}

TEST(BakeAccuracy, SmallAssetIsAccurateAndDeterministic) {
    BakeSettings s = test::small_bake_settings();
    s.step = 4;
    s.depth_samples = 32;
    s.scheme = DepthScheme::Log;
    s.z_max = 0.0;
    const Asset a = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("IB"), s);
    AccuracyOptions opt;
    opt.quadrature = {1e-7, 1e-15, 40};  // the default 1e-9 is for the docs' tables: slow
    opt.stride = 9;
    const auto rows = evaluate_asset_accuracy(a, opt, {1});
    const auto rows2 = evaluate_asset_accuracy(a, opt, {2});
    ASSERT_EQ(rows.size(), 5u);  // three planes, open water at z_max and to infinity
    for (std::size_t r = 0; r < rows.size(); ++r) {
        EXPECT_EQ(rows[r].mean_rel, rows2[r].mean_rel);
        EXPECT_EQ(rows[r].max_rel, rows2[r].max_rel);
        EXPECT_GE(rows[r].pixels, 40);
        EXPECT_LT(rows[r].mean_rel, 0.01) << rows[r].scene;
        EXPECT_LT(rows[r].max_rel, 0.05) << rows[r].scene;
    }
    EXPECT_EQ(rows[0].scene, "plane 2 m");
    // Truncating at the auto z_max costs at most its tolerance on top of interpolation.
    EXPECT_LE(rows[4].max_rel, rows[3].max_rel + 2.0 * s.tolerance);
}

}  // namespace
}  // namespace deepsea

namespace deepsea {

TEST_F(BakeFile, MultipleScatteringRoundTripAndDamage) {
    // A multiple-scattering asset: more light than single scattering at every column, the
    // record of how it was made, one lamp table per lamp (equal ones shared), all read back.
    BakeSettings s = test::small_bake_settings();
    const Asset single = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("3C"), s);
    s.scattering = Scattering::Multiple;
    s.higher_orders.paths = 512;
    s.higher_orders.lamp_samples = 32;
    const Asset a = bake(test::kBakeCam, test::two_lamp_rig(), jerlov_water("3C"), s);
    EXPECT_EQ(a.info.scattering, Scattering::Multiple);
    EXPECT_NE(a.info.input_hash, single.info.input_hash);
    EXPECT_GT(a.info.higher_orders.fraction, 0.1);  // 3C: far more than single scattering
    EXPECT_GT(a.info.higher_orders.rel_std_error, 0.0);
    const Lattice& l = a.lattice();
    for (int i = 0; i < l.ni; ++i)
        for (int j = 0; j < l.nj; ++j)
            for (int c = 0; c < 3; ++c)
                EXPECT_GT(a.at(i, j, l.slabs())[c], single.at(i, j, l.slabs())[c]);
    ASSERT_EQ(a.lamp_fields.size(), 2u);
    EXPECT_EQ(a.lamp_fields[0].sh, a.lamp_fields[1].sh);  // same profile: one bake

    write_asset(path("m.vdb"), a);
    const Asset b = load_asset(path("m.vdb"));
    EXPECT_EQ(b.info.scattering, Scattering::Multiple);
    EXPECT_EQ(b.info.higher_orders.paths, 512);
    EXPECT_EQ(b.info.higher_orders.lamp_samples, 32);
    EXPECT_EQ(b.info.input_hash, a.info.input_hash);
    // The columns' angle and the check of orders >= 2 (full float JSON: exact).
    const HigherOrderSettings &ha = a.info.higher_orders, &hb = b.info.higher_orders;
    EXPECT_GT(ha.spacing_rad, 0.0);
    EXPECT_EQ(hb.spacing_rad, ha.spacing_rad);
    ASSERT_TRUE(ha.check.done && hb.check.done);
    EXPECT_GT(ha.check.columns, 0);
    EXPECT_EQ(hb.check.mean_rel, ha.check.mean_rel);
    EXPECT_EQ(hb.check.max_rel, ha.check.max_rel);
    EXPECT_EQ(hb.check.max_u, ha.check.max_u);
    EXPECT_EQ(hb.check.columns, ha.check.columns);
    // The wall model (docs/model.md, "Water light in front of a surface") is recorded and read
    // back; an asset from before it (key absent) reads as water without walls.
    EXPECT_TRUE(ha.wall);
    EXPECT_TRUE(hb.wall);
    {
        BakeInfo before = a.info;
        before.higher_orders.wall = false;
        EXPECT_EQ(bake_info_to_json(before).find("\"wall\""), std::string::npos);
        EXPECT_FALSE(bake_info_from_json(bake_info_to_json(before)).higher_orders.wall);
        EXPECT_NE(input_hash(before), a.info.input_hash);  // bake-library re-bakes it
    }
    // Tail pooling is recorded and read back; an asset from before it reads as not pooled.
    EXPECT_EQ(ha.tail_above, kMsTailAbove);
    EXPECT_EQ(hb.tail_above, ha.tail_above);
    EXPECT_EQ(hb.tail_radius, ha.tail_radius);
    {
        BakeInfo before = a.info;
        before.higher_orders.tail_above = 0.0;
        EXPECT_EQ(bake_info_to_json(before).find("\"tail\""), std::string::npos);
        EXPECT_EQ(bake_info_from_json(bake_info_to_json(before)).higher_orders.tail_above, 0.0);
        EXPECT_NE(input_hash(before), a.info.input_hash);  // bake-library re-bakes it
    }
    // So are the threshold from the column's own mean, log-bilinear columns and the roulette
    // after each segment's next event; an asset from before them (keys absent) reads as the
    // single-scattering threshold, bilinear and the roulette before it.
    EXPECT_EQ(ha.tail_of_mean, kMsTailOfMean);
    EXPECT_EQ(hb.tail_of_mean, ha.tail_of_mean);
    EXPECT_TRUE(ha.log_between);
    EXPECT_TRUE(hb.log_between);
    EXPECT_TRUE(ha.lamp_symmetric);
    EXPECT_TRUE(hb.lamp_symmetric);
    EXPECT_TRUE(ha.roulette_after_next_event);
    EXPECT_TRUE(hb.roulette_after_next_event);
    {
        BakeInfo before = a.info;
        before.higher_orders.tail_of_mean = 0.0;
        before.higher_orders.log_between = false;
        before.higher_orders.lamp_symmetric = false;
        before.higher_orders.roulette_after_next_event = false;
        const std::string j = bake_info_to_json(before);
        EXPECT_EQ(j.find("of_mean"), std::string::npos);
        EXPECT_EQ(j.find("between_columns"), std::string::npos);
        EXPECT_EQ(j.find("lamp_symmetry"), std::string::npos);
        EXPECT_EQ(j.find("roulette"), std::string::npos);
        const HigherOrderSettings read = bake_info_from_json(j).higher_orders;
        EXPECT_EQ(read.tail_of_mean, 0.0);
        EXPECT_FALSE(read.log_between);
        EXPECT_FALSE(read.lamp_symmetric);
        EXPECT_FALSE(read.roulette_after_next_event);
        EXPECT_EQ(read.tail_above, ha.tail_above);
        EXPECT_NE(input_hash(before), a.info.input_hash);  // bake-library re-bakes it
        // A value it does not know is refused, naming the key.
        std::string bad = bake_info_to_json(a.info);
        const std::string key = "\"log-bilinear\"";
        bad.replace(bad.find(key), key.size(), "\"cubic\"");
        try {
            (void)bake_info_from_json(bad);
            ADD_FAILURE() << "between_columns \"cubic\" accepted";
        } catch (const std::exception& e) {
            EXPECT_NE(std::string(e.what()).find("between_columns"), std::string::npos);
        }
    }
    // The roulette after each segment's next event alone is another estimate: another request.
    {
        BakeInfo before = a.info;
        before.higher_orders.roulette_after_next_event = false;
        EXPECT_NE(input_hash(before), a.info.input_hash);
    }
    // An asset from before the angular rule and its check (keys absent) still reads: spacing
    // unknown (0), not checked.
    {
        BakeInfo before = a.info;
        before.higher_orders.spacing_rad = 0.0;
        before.higher_orders.check = {};
        const BakeInfo read = bake_info_from_json(bake_info_to_json(before));
        EXPECT_EQ(bake_info_to_json(before).find("spacing_rad"), std::string::npos);
        EXPECT_EQ(read.higher_orders.spacing_rad, 0.0);
        EXPECT_FALSE(read.higher_orders.check.done);
        EXPECT_EQ(read.higher_orders.stride, ha.stride);
    }
    ASSERT_EQ(b.lamp_fields.size(), 2u);
    for (std::size_t f = 0; f < 2; ++f) {
        EXPECT_EQ(b.lamp_fields[f].sh, a.lamp_fields[f].sh);  // full float: exact
        EXPECT_EQ(b.lamp_fields[f].nr, a.lamp_fields[f].nr);
        EXPECT_DOUBLE_EQ(b.lamp_fields[f].r_max, a.lamp_fields[f].r_max);
    }

    // A changed byte in the middle of the file: never a crash; if the loader notices (it reads
    // every grid it uses and checks their checksums), an AssetError.
    const auto size = fs::file_size(path("m.vdb"));
    {
        std::fstream f(path("m.vdb"), std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(size / 2));
        char ch = 0;
        f.read(&ch, 1);
        f.seekp(std::streamoff(size / 2));
        ch = char(ch ^ 0x5a);
        f.write(&ch, 1);
    }
    try {
        (void)load_asset(path("m.vdb"));
    } catch (const AssetError&) {
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not an AssetError: " << e.what();
    }
}

}  // namespace deepsea
