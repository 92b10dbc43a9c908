// The setup's `snow` section (docs/config.md): a preset by name, off, values over a preset or on
// their own, every bad value one line naming file, line and key, and the round trip through
// setup_to_yaml.

#include <gtest/gtest.h>

#include <string>

#include "../message_of.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"

namespace deepsea {

namespace {

Setup parse(const std::string& snow_text) { return parse_setup(snow_text, "s.yaml"); }

std::string error(const std::string& text) {
    return test::message_of<ConfigError>([&] { parse(text); });
}

}  // namespace

TEST(SnowConfig, PresetOffAndValues) {
    const deepsea::Setup a = parse("snow: nepheloid\n");
    ASSERT_TRUE(a.snow);
    const Snow want = snow_preset("nepheloid");
    EXPECT_EQ(a.snow->name, "nepheloid");
    EXPECT_EQ(a.snow->concentration, want.concentration);
    EXPECT_EQ(a.snow->slope, want.slope);
    EXPECT_FALSE(
        parse("snow: off\ncamera: {width: 4, height: 4, fx: 4, fy: 4, cx: 2, cy: 2}\n").snow);

    const deepsea::Setup b =
        parse("snow:\n  preset: plume\n  albedo: 0.25\n  max_distance_m: 1.5\n");
    const Snow plume = snow_preset("plume");
    EXPECT_EQ(b.snow->name, "custom");  // no longer the preset
    EXPECT_EQ(b.snow->albedo, 0.25);
    EXPECT_EQ(b.snow->max_distance_m, 1.5);
    EXPECT_EQ(b.snow->concentration, plume.concentration);
    EXPECT_EQ(b.snow->d_min_mm, plume.d_min_mm);
    // The preset's own value given again keeps its name.
    EXPECT_EQ(
        parse("snow: {preset: plume, slope: " + std::to_string(plume.slope) + "}\n").snow->name,
        "plume");

    const deepsea::Setup c =
        parse("snow: {concentration: 300, d_min_mm: 1, d_max_mm: 2, slope: 0}\n");
    EXPECT_EQ(c.snow->name, "custom");
    EXPECT_EQ(c.snow->concentration, 300.0);
    EXPECT_EQ(c.snow->d_max_mm, 2.0);
    EXPECT_EQ(c.snow->albedo, Snow{}.albedo);

    // Motion streaks: how the snow is drawn, so the preset keeps its name; off by default.
    EXPECT_FALSE(a.snow->streaks);
    const deepsea::Setup d =
        parse("snow: {preset: plume, streaks: true, exposure_time_ms: 20, frame_rate_hz: 15}\n");
    EXPECT_EQ(d.snow->name, "plume");
    EXPECT_TRUE(d.snow->streaks);
    EXPECT_EQ(d.snow->exposure_time_ms, 20.0);
    EXPECT_EQ(d.snow->frame_rate_hz, 15.0);
}

TEST(SnowConfig, BadValuesNameFileLineAndKey) {
    const struct {
        std::string text, starts;
    } cases[] = {
        {"snow: blizzard\n", "s.yaml:1: snow: "},
        {"snow:\n  preset: plume\n  albedo: 1.5\n", "s.yaml:3: snow.albedo: must be in (0, 1]"},
        {"snow:\n  concentration: -3\n", "s.yaml:2: snow.concentration: "},
        {"snow:\n  concentration: 10\n  d_min_mm: 2\n  d_max_mm: 1\n", "s.yaml:4: snow.d_max_mm: "},
        {"snow:\n  preset: abyssal\n  slope: 7\n", "s.yaml:3: snow.slope: "},
        {"snow:\n  preset: abyssal\n  max_distance_m: 0.05\n", "s.yaml:3: snow.max_distance_m: "},
        {"snow:\n  albedo: 0.5\n", "s.yaml:1: snow.concentration: "},  // no preset: required
        {"snow:\n  preset: abyssal\n  density: 3\n", "s.yaml:3: snow.density: "},
        {"snow:\n  preset: abyssal\n  exposure_time_ms: 0\n", "s.yaml:3: snow.exposure_time_ms: "},
        {"snow:\n  preset: abyssal\n  frame_rate_hz: -30\n", "s.yaml:3: snow.frame_rate_hz: "},
        {"snow:\n  preset: abyssal\n  streaks: maybe\n", "s.yaml:3: snow.streaks: "},
    };
    for (const auto& c : cases) {
        const std::string m = error(c.text);
        EXPECT_EQ(m.rfind(c.starts, 0), 0u) << c.text << " -> " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
    EXPECT_NE(error("snow: blizzard\n").find("blizzard"), std::string::npos);
}

TEST(SnowConfig, RoundTripThroughYaml) {
    for (const std::string text :
         {"snow: abyssal\n", "snow: {preset: nepheloid, albedo: 0.3}\n",
          "snow: {concentration: 123.456, d_min_mm: 0.3, d_max_mm: 7, slope: 2.5, albedo: 0.9, "
          "max_distance_m: 6}\n",
          "snow: {preset: plume, streaks: true, exposure_time_ms: 4.5, frame_rate_hz: 12.5}\n"}) {
        const deepsea::Setup a = parse(text);
        const deepsea::Setup b = parse_setup(setup_to_yaml(a), "round.yaml");
        ASSERT_TRUE(b.snow) << text;
        EXPECT_EQ(b.snow->name, a.snow->name);
        EXPECT_EQ(b.snow->concentration, a.snow->concentration);
        EXPECT_EQ(b.snow->d_min_mm, a.snow->d_min_mm);
        EXPECT_EQ(b.snow->d_max_mm, a.snow->d_max_mm);
        EXPECT_EQ(b.snow->slope, a.snow->slope);
        EXPECT_EQ(b.snow->albedo, a.snow->albedo);
        EXPECT_EQ(b.snow->max_distance_m, a.snow->max_distance_m);
        EXPECT_EQ(b.snow->streaks, a.snow->streaks);
        EXPECT_EQ(b.snow->exposure_time_ms, a.snow->exposure_time_ms);
        EXPECT_EQ(b.snow->frame_rate_hz, a.snow->frame_rate_hz);
    }
}

}  // namespace deepsea
