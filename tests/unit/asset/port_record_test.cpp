// The asset's port record (docs/asset-format.md, "port"): written and read back exactly, part of
// the input hash, absent (and hashed as before ports) for pinhole assets, checked on reading.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <string>

#include "deepsea/asset/asset.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"
#include "test_assets.h"

namespace deepsea {
namespace {

const Camera kCam{64, 48, 50.0, 52.0, 31.5, 23.0};

Rgb field(double u, double v, double z) { return Rgb{1.0, 2.0, 3.0} * ((1.0 + 0.01 * u + v) * z); }

Port dispersive_flat() {
    Port p;
    p.flat.normal = {0.05, -0.02, 1.0};  // kept as written, not normalised
    p.flat.distance = 0.031;
    p.flat.glass_thickness = 0.0125;
    p.n_glass = 1.517;
    p.n_water = {1.339, 1.342, 1.347};
    p.fresnel = true;
    return p;
}

Port decentred_dome() {
    Port p;
    p.kind = PortKind::Dome;
    p.dome.centre = {0.003, -0.001, 0.002};
    p.dome.radius = 0.05;
    p.dome.glass_thickness = 0.008;
    return p;
}

}  // namespace

TEST(PortRecord, RoundTripsExactlyAndEntersTheHash) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Log, 7, 4.25, field);
    const std::string pinhole_hash = input_hash(a.info);
    for (const Port& port : {dispersive_flat(), decentred_dome()}) {
        a.info.port = port;
        a.info.input_hash = input_hash(a.info);
        EXPECT_NE(a.info.input_hash, pinhole_hash) << describe(port);
        const BakeInfo b = bake_info_from_json(bake_info_to_json(a.info));
        ASSERT_TRUE(b.port.has_value());
        EXPECT_TRUE(same_rays(*b.port, port)) << describe(*b.port);
        EXPECT_EQ(b.port->fresnel, port.fresnel);
        EXPECT_EQ(describe(*b.port), describe(port));
        EXPECT_EQ(input_hash(b), a.info.input_hash);
    }
    // Another port is another bake.
    Port moved = dispersive_flat();
    moved.flat.distance = 0.032;
    a.info.port = dispersive_flat();
    const std::string h = input_hash(a.info);
    a.info.port = moved;
    EXPECT_NE(input_hash(a.info), h);
}

TEST(PortRecord, AssetWithoutAPortReadsAsPinholeAndHashesAsBefore) {
    // An asset written before ports has no "port" key: it reads back without one, and its hash
    // is computed from the same keys as then (a library stays up to date).
    Asset a = test::function_asset(kCam, 8, DepthScheme::Log, 7, 4.25, field);
    a.info.input_hash = input_hash(a.info);
    const std::string text = bake_info_to_json(a.info);
    EXPECT_EQ(text.find("\"port\""), std::string::npos);
    const BakeInfo b = bake_info_from_json(text);
    EXPECT_FALSE(b.port.has_value());
    EXPECT_EQ(input_hash(b), a.info.input_hash);
    EXPECT_NO_THROW(check_port(a, std::nullopt, false));
}

TEST(PortRecord, DamagedPortIsRefusedNamingTheKey) {
    Asset a = test::function_asset(kCam, 8, DepthScheme::Log, 7, 4.25, field);
    a.info.port = dispersive_flat();
    nlohmann::json j = nlohmann::json::parse(bake_info_to_json(a.info));
    const auto refused = [&](nlohmann::json bad, const std::string& key) {
        try {
            bake_info_from_json(bad.dump());
            ADD_FAILURE() << "accepted " << key;
        } catch (const AssetError& e) {
            EXPECT_NE(std::string(e.what()).find("deepsea:bake: " + key + ":"), std::string::npos)
                << e.what();
        }
    };
    nlohmann::json bad = j;
    bad["port"]["flat"]["glass_thickness"] = 0.0;
    refused(bad, "port.flat.glass_thickness");
    bad = j;
    bad["port"]["flat"].erase("distance");
    refused(bad, "port.flat.distance");
    bad = j;
    bad["port"]["flat"]["n_water"] = {1.34, 1.34};
    refused(bad, "port.flat.n_water");
    bad = j;
    bad["port"]["dome"] = bad["port"]["flat"];
    refused(bad, "port");
}

}  // namespace deepsea
