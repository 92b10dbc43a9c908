#include "deepsea/optics/water_presets.h"

#include <gtest/gtest.h>

#include <string>

#include "deepsea/core/error.h"
#include "deepsea/optics/deep_ocean.h"
#include "deepsea/optics/jerlov.h"

namespace deepsea {
namespace {

TEST(DeepOcean, PresetsArePhysical) {
    ASSERT_EQ(deep_ocean_types().size(), 3u);
    for (const auto& t : deep_ocean_types()) {
        const Water w = deep_ocean_water(t);
        EXPECT_EQ(w.name, "deep-" + t);
        for (int c = 0; c < 3; ++c) {
            EXPECT_GT(w.b[c], 0.0) << t;
            EXPECT_LE(w.b[c], w.c[c]) << t;
        }
        // Pure water absorbs red most; the particle term (lambda^-gamma) never turns that round.
        EXPECT_GT(w.c.r, w.c.g) << t;
        EXPECT_GT(w.c.r, w.c.b) << t;
        EXPECT_GT(w.c.g, w.c.b) << t;
    }
    EXPECT_THROW(deep_ocean_water("murky"), ConfigError);
}

/// docs/water.md: the table of band means.
struct DocumentedRow {
    const char* type;
    Rgb c, b;
    PhaseKind phase;
};
// clang-format off
const DocumentedRow kDocumented[] = {
    {"clear",     {0.3956, 0.0949, 0.0429}, {0.0192, 0.0235, 0.0309}, PhaseKind::PetzoldClear},
    {"moderate",  {0.4361, 0.1404, 0.0952}, {0.0557, 0.0645, 0.0780}, PhaseKind::PetzoldClear},
    {"nepheloid", {0.5770, 0.2901, 0.2560}, {0.1824, 0.1992, 0.2227}, PhaseKind::PetzoldCoastal},
};
// clang-format on

TEST(DeepOcean, ValuesAsDocumented) {
    for (const DocumentedRow& row : kDocumented) {
        const Water w = deep_ocean_water(row.type);
        for (int c = 0; c < 3; ++c) {
            EXPECT_DOUBLE_EQ(w.c[c], row.c[c]) << row.type << " c[" << c << "]";
            EXPECT_DOUBLE_EQ(w.b[c], row.b[c]) << row.type << " b[" << c << "]";
        }
        EXPECT_EQ(w.phase.kind, row.phase) << row.type;
    }
}

TEST(DeepOcean, TurbidityOrdersThePresets) {
    const Water clear = deep_ocean_water("clear"), moderate = deep_ocean_water("moderate"),
                neph = deep_ocean_water("nepheloid");
    for (int c = 0; c < 3; ++c) {
        EXPECT_LT(clear.c[c], moderate.c[c]);
        EXPECT_LT(moderate.c[c], neph.c[c]);
        EXPECT_LT(clear.b[c], moderate.b[c]);
        EXPECT_LT(moderate.b[c], neph.b[c]);
    }
    // The point of the presets: clear deep water scatters far less than Jerlov's clearest type.
    const Water ib = jerlov_water("IB");
    for (int c = 0; c < 3; ++c) {
        EXPECT_LT(clear.b[c], 0.5 * ib.b[c]);
        EXPECT_LT(clear.c[c], ib.c[c]);
    }
}

TEST(WaterPresets, ResolvesEveryFamilyAndListsThemInErrors) {
    EXPECT_EQ(water_preset("jerlov:IB").name, "jerlov-IB");
    EXPECT_EQ(water_preset("jerlov:5C").c.g, jerlov_water("5C").c.g);
    EXPECT_EQ(water_preset("deep:clear").name, "deep-clear");
    EXPECT_EQ(water_preset("deep:nepheloid").c.r, deep_ocean_water("nepheloid").c.r);
    EXPECT_EQ(water_preset_names().size(), jerlov_types().size() + deep_ocean_types().size());
    for (const auto& n : water_preset_names()) {
        EXPECT_TRUE(is_water_preset(n)) << n;
        EXPECT_NO_THROW(water_preset(n)) << n;
    }
    EXPECT_TRUE(is_water_preset("deep:murky"));  // a preset spec, if an unknown one
    EXPECT_FALSE(is_water_preset("waters/deep-clear.yaml"));
    for (const std::string bad : {"deep:murky", "jerlov:IV", "deep:", "deep:Clear"}) {
        try {
            water_preset(bad);
            ADD_FAILURE() << bad;
        } catch (const ConfigError& e) {
            const std::string what = e.what();
            EXPECT_NE(what.find("'" + bad + "'"), std::string::npos) << what;
            EXPECT_NE(what.find("jerlov:IB"), std::string::npos) << what;
            EXPECT_NE(what.find("deep:clear"), std::string::npos) << what;
            EXPECT_NE(what.find("deep:nepheloid"), std::string::npos) << what;
        }
    }
}

}  // namespace
}  // namespace deepsea
