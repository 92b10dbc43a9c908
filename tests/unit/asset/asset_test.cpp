#include "deepsea/asset/asset.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <nlohmann/json.hpp>

#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"
#include "test_assets.h"

namespace deepsea {
namespace {

const Camera kCam{64, 48, 50.0, 52.0, 31.5, 23.0};

/// Functions that trilinear interpolation reproduces exactly: linear in z, bilinear in u, v.
Rgb bilinear_field(double u, double v, double z) {
    return Rgb{1.0, 2.0, 3.0} * ((1.0 + 0.01 * u) * (2.0 + 0.02 * v) * z) +
           Rgb{0.0, 0.0, 1e-3 * u * z};
}

TEST(AssetSample, EqualsNodeValues) {
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Sqrt, 12, 6.0, test::smooth_field);
    const Lattice& l = a.lattice();
    for (int i = 0; i < l.ni; i += 3) {
        for (int j = 0; j < l.nj; j += 2) {
            for (int k = 0; k < l.nk(); ++k) {
                const Rgb s = a.sample(l.u(i), l.v(j), l.z[k]);
                const Rgb x = a.at(i, j, k);
                for (int c = 0; c < 3; ++c)
                    EXPECT_NEAR(s[c], x[c], 1e-12) << i << " " << j << " " << k;
            }
        }
    }
}

TEST(AssetSample, InterpolatesLinearly) {
    for (DepthScheme scheme : {DepthScheme::Uniform, DepthScheme::Log, DepthScheme::Taylor}) {
        const Asset a = test::function_asset(kCam, 8, scheme, 10, 5.0, bilinear_field);
        for (double u : {0.0, 3.3, 17.9, 40.0, 63.0}) {
            for (double v : {0.0, 5.5, 23.0, 47.0}) {
                for (double z : {0.01, 0.7, 2.5, 4.99}) {
                    const Rgb s = a.sample(u, v, z);
                    const Rgb x = bilinear_field(u, v, z);
                    for (int c = 0; c < 3; ++c) {
                        EXPECT_NEAR(s[c], x[c], 2e-6 * std::abs(x[c]) + 1e-9)
                            << to_string(scheme) << " " << u << " " << v << " " << z;
                    }
                }
            }
        }
    }
}

TEST(AssetSample, ConstantBeyondZmaxZeroAtCameraClampedOutside) {
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 10, 5.0, bilinear_field);
    const Rgb at_max = a.sample(20.0, 10.0, 5.0);
    for (double z : {5.0001, 50.0, double(INFINITY), double(NAN)}) {
        const Rgb s = a.sample(20.0, 10.0, z);
        for (int c = 0; c < 3; ++c) EXPECT_EQ(s[c], at_max[c]) << z;
    }
    const Rgb zero = a.sample(20.0, 10.0, 0.0);
    const Rgb neg = a.sample(20.0, 10.0, -1.0);
    for (int c = 0; c < 3; ++c) {
        EXPECT_EQ(zero[c], 0.0);
        EXPECT_EQ(neg[c], 0.0);
    }
    // Outside the lattice the nearest column's value is used.
    const Rgb edge = a.sample(0.0, 10.0, 2.0);
    const Rgb out = a.sample(-5.0, 10.0, 2.0);
    for (int c = 0; c < 3; ++c) EXPECT_EQ(edge[c], out[c]);
}

TEST(CheckCamera, SameCameraAndSameViewPass) {
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    EXPECT_NO_THROW(check_camera(a, kCam));
    // half resolution: pixel edges scale, centres sit at integers, so cx -> (cx - 0.5) / 2
    const Camera half{32, 24, 25.0, 26.0, 15.5, 11.25};
    EXPECT_NO_THROW(check_camera(a, half));
}

TEST(CheckCamera, OtherCameraIsRefusedNamingBoth) {
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    const Camera other{64, 48, 80.0, 80.0, 32.0, 24.0};
    try {
        check_camera(a, other);
        FAIL() << "no AssetError";
    } catch (const AssetError& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("fx=50"), std::string::npos) << msg;
        EXPECT_NE(msg.find("fx=80"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(BakeInfoJson, RoundTrips) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Log, 7, 4.25, bilinear_field);
    a.info.z_max_auto = true;
    a.info.tolerance = 5e-4;
    a.info.rig.lights[1].rid.kind = Rid::Kind::Table;
    a.info.rig.lights[1].rid.angle_deg = {0.0, 10.0, 45.0};
    a.info.rig.lights[1].rid.value = {1.0, 0.8, 0.1};
    a.info.rig.lights[1].rid.cutoff_deg = 60.0;
    a.info.water.forward.enabled = true;
    a.info.water.forward.G = {0.2, 0.1, 0.1};
    a.info.water.forward.k = 0.05;
    a.info.input_hash = input_hash(a.info);

    const BakeInfo b = bake_info_from_json(bake_info_to_json(a.info));
    const BakeInfo& x = a.info;
    EXPECT_TRUE(b.camera == x.camera);
    EXPECT_TRUE(b.lattice == x.lattice);
    EXPECT_EQ(b.z_max_auto, true);
    EXPECT_EQ(b.tolerance, 5e-4);
    EXPECT_EQ(b.baker_version, x.baker_version);
    EXPECT_EQ(b.input_hash, x.input_hash);
    ASSERT_EQ(b.rig.lights.size(), 2u);
    EXPECT_EQ(b.rig.name, "two-lamps");
    EXPECT_EQ(b.rig.lights[0].position.x, x.rig.lights[0].position.x);
    EXPECT_EQ(b.rig.lights[0].direction.z, x.rig.lights[0].direction.z);
    EXPECT_EQ(b.rig.lights[0].intensity.b, 0.8);
    EXPECT_EQ(b.rig.lights[1].rid.kind, Rid::Kind::Table);
    EXPECT_EQ(b.rig.lights[1].rid.value, x.rig.lights[1].rid.value);
    EXPECT_EQ(b.rig.lights[1].rid.cutoff_deg, 60.0);
    EXPECT_EQ(b.water.c.r, x.water.c.r);
    EXPECT_EQ(b.water.b.b, x.water.b.b);
    EXPECT_EQ(b.water.phase.kind, PhaseKind::HenyeyGreenstein);
    EXPECT_EQ(b.water.phase.g, 0.9);
    EXPECT_TRUE(b.water.forward.enabled);
    EXPECT_EQ(b.water.forward.k, 0.05);
    EXPECT_EQ(input_hash(b), x.input_hash);  // the inputs survive exactly
}

TEST(BakeInfoJson, MalformedIsAssetError) {
    EXPECT_THROW(bake_info_from_json("{not json"), AssetError);
    EXPECT_THROW(bake_info_from_json("[]"), AssetError);
    EXPECT_THROW(bake_info_from_json("{\"baker_version\": \"x\"}"), AssetError);
    const Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    std::string j = bake_info_to_json(a.info);
    j.replace(j.find("\"fx\""), 4, "\"fz\"");
    EXPECT_THROW(bake_info_from_json(j), AssetError);
}

TEST(BakeInfoJson, UsesTheSchemasKeysAndRanges) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    a.info.rig.lights[1].rid.kind = Rid::Kind::Table;
    a.info.rig.lights[1].rid.angle_deg = {0.0, 45.0};
    a.info.rig.lights[1].rid.value = {1.0, 0.1};
    a.info.water.forward = ForwardScatter{true, {0.2, 0.1, 0.1}, 0.05};
    const nlohmann::json j = nlohmann::json::parse(bake_info_to_json(a.info));
    // Every key the JSON writes is a key of the YAML schema (optics/schema.h).
    auto within = [](const nlohmann::json& obj, const std::vector<std::string>& keys) {
        for (const auto& [k, v] : obj.items())
            EXPECT_NE(std::find(keys.begin(), keys.end(), k), keys.end()) << k;
    };
    within(j["camera"], schema::kCamera);
    within(j["rig"], schema::kRig);
    for (const auto& l : j["rig"]["lights"]) {
        within(l, schema::kLight);
        within(l["rid"], schema::kRid);
    }
    within(j["rig"]["lights"][0]["rid"]["gaussian"], schema::kRidGaussian);
    within(j["rig"]["lights"][1]["rid"]["table"], schema::kRidTable);
    within(j["water"], schema::kWater);
    within(j["water"]["phase"], schema::kPhase);
    within(j["water"]["forward_scatter"], schema::kForwardScatter);

    // The schema's range checks apply to the asset too, naming the key.
    auto refused = [&](const char* pointer, const nlohmann::json& value, const char* key) {
        nlohmann::json bad = j;
        bad[nlohmann::json::json_pointer(pointer)] = value;
        try {
            bake_info_from_json(bad.dump());
            ADD_FAILURE() << "accepted " << pointer;
        } catch (const AssetError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(std::string("deepsea:bake: ") + key + ": ", 0),
                      0u)
                << e.what();
        }
    };
    refused("/camera/fx", -1.0, "camera.fx");
    refused("/rig/lights/0/intensity/1", -1.0, "rig.lights[0].intensity");
    refused("/rig/lights/0/position", nlohmann::json::array({0.0, 0.0, 0.01}),
            "rig.lights[0].position");
    refused("/rig/lights/1/rid/table/angle_deg/1", 200.0, "rig.lights[1].rid.table.angle_deg[1]");
    refused("/water/scattering/0", 1.0, "water.scattering");
}

TEST(InputHash, ChangesWithInputsNotWithResults) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    const std::string h = input_hash(a.info);
    EXPECT_EQ(h.rfind("fnv1a64:", 0), 0u);
    EXPECT_EQ(h.size(), 8u + 16u);
    BakeInfo other = a.info;
    other.baker_version = "another";
    EXPECT_EQ(input_hash(other), h);
    other.rig.lights[0].intensity.r = 2.0;
    EXPECT_NE(input_hash(other), h);
    other = a.info;
    other.lattice.step = 4;
    EXPECT_NE(input_hash(other), h);
    // With auto z_max the hash names the tolerance, not the depth found.
    other = a.info;
    other.z_max_auto = true;
    other.tolerance = 1e-3;
    const std::string ha = input_hash(other);
    other.lattice.z = depth_samples(DepthScheme::Uniform, 4, 6.0);
    EXPECT_EQ(input_hash(other), ha);
}

}  // namespace
TEST(BakeInfoJson, LampRadiusIsWrittenOnlyWhereNotTheDefault) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Uniform, 4, 5.0, bilinear_field);
    const std::string plain = bake_info_to_json(a.info);
    // the default radius is not written: such assets (and their input hashes) stay as before
    EXPECT_EQ(plain.find("radius"), std::string::npos);
    EXPECT_EQ(bake_info_from_json(plain).rig.lights[0].radius, kDefaultLampRadius);
    const std::string hash = input_hash(a.info);
    a.info.rig.lights[0].radius = 0.08;
    EXPECT_NE(input_hash(a.info), hash);
    const BakeInfo back = bake_info_from_json(bake_info_to_json(a.info));
    EXPECT_EQ(back.rig.lights[0].radius, 0.08);
    EXPECT_EQ(back.rig.lights[1].radius, kDefaultLampRadius);
    nlohmann::json j = nlohmann::json::parse(bake_info_to_json(a.info));
    j["rig"]["lights"][0]["radius"] = 2.0;
    EXPECT_THROW(bake_info_from_json(j.dump()), AssetError);
}

}  // namespace deepsea
