// The auto-exposure controller (auto_exposure.h, docs/camera.md, "Auto exposure"): on frames the
// stage records from flat radiance fields, it settles on a step of scene brightness within the
// frames settle_frames states, never leaves its limits, and gives the same bits for the same
// inputs; both meters; bad settings refused naming the key.
#include "deepsea/camera/auto_exposure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "camera_test_util.h"
#include "deepsea/camera/sensor.h"

namespace deepsea {
namespace {

using namespace camera_test;

const double kTol = std::log(1.05);  // settled: the metered level within 5 % of the target

CameraModel ae_model(bool noise) {
    CameraModel m = flat_model();
    m.sensor.noise = noise;
    AutoExposure& ae = m.auto_exposure;
    ae.enabled = true;  // the defaults: 99th percentile to 0.5, d = 0.5, 0.01-30 ms, K0-16 K0
    return m;
}

/// The settings and readings of a sequence, frame by frame, as a sequence renderer makes them.
struct Sequence {
    std::vector<FrameExposure> exposures;
    std::vector<ExposureReading> readings;
};

Sequence record(const CameraStage& stage, const std::function<const Image&(int)>& scene, int frames,
                FrameExposure start, const Parallel& par = {}, int first_key = 0) {
    CameraLayerSet layers;
    layers.raw = true;
    CameraOutput out;
    Sequence r;
    FrameExposure e = start;
    for (int k = 0; k < frames; ++k) {
        stage.apply(out, scene(k), std::uint64_t(first_key + k), e, layers, par);
        r.exposures.push_back(out.exposure);
        r.readings.push_back(meter_exposure(stage.model(), out));
        e = next_exposure(stage.model(), out);
    }
    return r;
}

double log_error(const ExposureReading& r, double target) {
    return std::fabs(std::log(r.level / target));
}

/// Every frame's settings within the limits, and gain above its minimum only at the longest
/// exposure time (time first, then gain).
void expect_within(const Sequence& r, const ExposureLimits& l) {
    for (std::size_t k = 0; k < r.exposures.size(); ++k) {
        const FrameExposure& e = r.exposures[k];
        EXPECT_GE(e.exposure_time_ms, l.min_exposure_time_ms) << k;
        EXPECT_LE(e.exposure_time_ms, l.max_exposure_time_ms) << k;
        EXPECT_GE(e.system_gain, l.min_system_gain) << k;
        EXPECT_LE(e.system_gain, l.max_system_gain) << k;
        if (e.system_gain > l.min_system_gain) {
            EXPECT_EQ(e.exposure_time_ms, l.max_exposure_time_ms) << k;
        }
    }
}

/// The flat field (G brightest) whose 99th percentile at 10 ms and the sensor's gain is the
/// target, noise-free, times `scale`.
Image field(const CameraStage& stage, double scale) {
    const Sensor& s = stage.model().sensor;
    const double range = max_dn(s) - black_level(s);
    const double g = stage.model().auto_exposure.target * range /
                     (system_gain(s) * stage.electrons_per_radiance(1, 10.0));
    return flat(64, 48, Rgb(0.8 * g, g, 0.6 * g) * scale);
}

TEST(AutoExposure, SettleFramesFormula) {
    AutoExposure ae;  // target 0.5, d = 0.5
    // Down x10: e = ln 10 = 2.303, ceil(ln(0.0488 / 2.303) / ln 0.5) = ceil(5.56) = 6.
    EXPECT_EQ(settle_frames(ae, 0.1, kTol), 6);
    // Up x10 saturates (5 x the clip): a = ln(1 / 0.5), floor(2.303 / 0.693) = 3 frames clipped,
    // then ceil(ln(0.0488 / 0.693) / ln 0.5) = 4.
    EXPECT_EQ(settle_frames(ae, 10.0, kTol), 7);
    // x1.8 reaches 0.9, below 0.95 of the clip: damped only, ceil(ln(0.0488 / 0.588) / ln 0.5).
    EXPECT_EQ(settle_frames(ae, 1.8, kTol), 4);
    EXPECT_EQ(settle_frames(ae, 1.04, kTol), 0);  // within the tolerance already
    ae.damping = 1.0;
    EXPECT_EQ(settle_frames(ae, 0.1, kTol), 1);
    ae.damping = 0.25;  // ceil(ln(0.0488 / 2.303) / ln 0.75) = ceil(13.4) = 14
    EXPECT_EQ(settle_frames(ae, 0.1, kTol), 14);
}

/// Brightness L0, x10, L0, L0 / 10 (into gain), 20 frames each: each step settles within
/// settle_frames and stays settled; without noise the non-saturating steps settle exactly then.
void step_sequence(bool noise) {
    const CameraModel m = ae_model(noise);
    const CameraStage stage(m, pinhole(64, 48, 50.0));
    const double scales[] = {1.0, 10.0, 1.0, 0.1};
    std::vector<Image> phases;
    for (double s : scales) phases.push_back(field(stage, s));
    const int n = 20;
    const Sequence r = record(
        stage, [&](int k) -> const Image& { return phases[std::size_t(k / n)]; }, 4 * n,
        first_exposure(m));
    const ExposureLimits lim = exposure_limits(m.auto_exposure, m.sensor);
    expect_within(r, lim);
    const double target = m.auto_exposure.target;
    for (int p = 0; p < 4; ++p) {
        const int settle =
            p == 0 ? 0 : settle_frames(m.auto_exposure, scales[p] / scales[p - 1], kTol);
        for (int k = p * n + settle; k < (p + 1) * n; ++k)
            EXPECT_LE(log_error(r.readings[std::size_t(k)], target), kTol)
                << "phase " << p << " frame " << k << " (settle " << settle << ")";
        if (!noise && p >= 2) {  // exact: one frame earlier it is not settled yet
            EXPECT_GT(log_error(r.readings[std::size_t(p * n + settle - 1)], target), kTol) << p;
        }
    }
    // x10 brighter: exposure time a tenth of 10 ms; x10 darker: 30 ms and the rest in gain.
    EXPECT_NEAR(r.exposures[2 * n - 1].exposure_time_ms, 1.0, 0.05);
    EXPECT_EQ(r.exposures[2 * n - 1].system_gain, lim.min_system_gain);
    EXPECT_EQ(r.exposures[4 * n - 1].exposure_time_ms, lim.max_exposure_time_ms);
    // (With noise the 99th percentile lies about 2.3 sigma above the mean: at the 500 e- of the
    // dark phase that is 10 % more signal, so less gain.)
    EXPECT_NEAR(r.exposures[4 * n - 1].system_gain / lim.min_system_gain, 100.0 / 30.0,
                noise ? 0.4 : 0.05);
}

TEST(AutoExposure, SettlesOnStepsOfTenWithinTheStatedFrames) { step_sequence(false); }
TEST(AutoExposure, SettlesOnStepsOfTenWithNoise) { step_sequence(true); }

TEST(AutoExposure, FullDampingLandsInOneFrame) {
    CameraModel m = ae_model(false);
    m.auto_exposure.damping = 1.0;
    const CameraStage stage(m, pinhole(64, 48, 50.0));
    const Image dark = field(stage, 0.1);
    const Sequence r = record(
        stage, [&](int) -> const Image& { return dark; }, 3, first_exposure(m));
    EXPECT_GT(log_error(r.readings[0], 0.5), 2.0);
    // Within the first reading's rounding to whole DN (0.5 DN of 201).
    EXPECT_LE(log_error(r.readings[1], 0.5), 3e-3);
    EXPECT_LE(log_error(r.readings[2], 0.5), 3e-3);
}

TEST(AutoExposure, SitsAtItsLimitsWhenTheSceneIsOutOfReach) {
    const CameraModel m = ae_model(true);
    const CameraStage stage(m, pinhole(64, 48, 50.0));
    const ExposureLimits lim = exposure_limits(m.auto_exposure, m.sensor);
    EXPECT_EQ(lim.min_system_gain, system_gain(m.sensor));
    EXPECT_EQ(lim.max_system_gain, 16.0 * system_gain(m.sensor));
    const Image dark = field(stage, 1e-4), bright = field(stage, 1e4),
                black = flat(64, 48, Rgb(0.0));
    for (const Image* scene : {&dark, &black}) {
        const Sequence r = record(
            stage, [&](int) -> const Image& { return *scene; }, 30, first_exposure(m));
        expect_within(r, lim);
        EXPECT_EQ(r.exposures.back().exposure_time_ms, lim.max_exposure_time_ms);
        EXPECT_EQ(r.exposures.back().system_gain, lim.max_system_gain);
    }
    const Sequence r = record(
        stage, [&](int) -> const Image& { return bright; }, 30, first_exposure(m));
    expect_within(r, lim);
    EXPECT_TRUE(r.readings.back().saturated);
    EXPECT_EQ(r.exposures.back().exposure_time_ms, lim.min_exposure_time_ms);
    EXPECT_EQ(r.exposures.back().system_gain, lim.min_system_gain);
    // A start outside the limits is clamped into them.
    CameraModel out = m;
    out.sensor.exposure_time_ms = 100.0;
    out.sensor.system_gain = 1e-3;
    const FrameExposure f = first_exposure(out);
    EXPECT_EQ(f.exposure_time_ms, 30.0);
    EXPECT_EQ(f.system_gain, 1e-3);  // min_system_gain follows the sensor's K
    out.auto_exposure.min_system_gain = 0.1;
    EXPECT_EQ(first_exposure(out).system_gain, 0.1);
}

TEST(AutoExposure, SplitUsesTimeFirstThenGain) {
    const ExposureLimits l{0.01, 30.0, 0.5, 8.0};
    const auto at = [&](double x) { return split_exposure(x, l); };
    EXPECT_EQ(at(5.0).exposure_time_ms, 10.0);
    EXPECT_EQ(at(5.0).system_gain, 0.5);
    EXPECT_EQ(at(60.0).exposure_time_ms, 30.0);
    EXPECT_EQ(at(60.0).system_gain, 2.0);
    EXPECT_EQ(at(1e9).system_gain, 8.0);  // clamped to t_max K_max
    EXPECT_EQ(at(0.0).exposure_time_ms, 0.01);
    EXPECT_EQ(at(0.0).system_gain, 0.5);
}

TEST(AutoExposure, SameInputsSameBitsAndResumable) {
    const CameraModel m = ae_model(true);
    const CameraStage stage(m, pinhole(64, 48, 50.0));
    std::vector<Image> phases = {field(stage, 0.3), field(stage, 7.0)};
    const auto scene = [&](int k) -> const Image& { return phases[k < 8 ? 0 : 1]; };
    const Sequence a = record(stage, scene, 16, first_exposure(m), Parallel(1));
    const Sequence b =
        record(CameraStage(m, stage.camera()), scene, 16, first_exposure(m), Parallel(2, 1));
    ASSERT_EQ(a.exposures.size(), b.exposures.size());
    for (std::size_t k = 0; k < a.exposures.size(); ++k) {
        EXPECT_EQ(std::memcmp(&a.exposures[k], &b.exposures[k], sizeof(FrameExposure)), 0) << k;
        EXPECT_EQ(std::memcmp(&a.readings[k].level, &b.readings[k].level, sizeof(double)), 0) << k;
    }
    // Resumed from frame 10's recorded settings: frames 10-15 again, bit for bit.
    const Sequence c = record(
        stage, [&](int k) -> const Image& { return scene(k + 10); }, 6, a.exposures[10], {}, 10);
    for (std::size_t k = 0; k < 6; ++k)
        EXPECT_EQ(std::memcmp(&c.exposures[k], &a.exposures[k + 10], sizeof(FrameExposure)), 0)
            << k;
}

/// Raw DN by hand: pixel i has 64 + 10 (i + 1) in one channel (cycling R, G, B), 64 in the others.
TEST(AutoExposure, MetersThePercentileOrTheMeanOfTheBrightestChannel) {
    const Sensor s;  // 12 bits, black 64, range 4031
    Image raw(10, 10, 3);
    for (int i = 0; i < 100; ++i) {
        for (int c = 0; c < 3; ++c) raw.data[std::size_t(3 * i + c)] = 64.0f;
        raw.data[std::size_t(3 * i + i % 3)] = float(64 + 10 * (i + 1));
    }
    AutoExposure ae;
    ae.percentile = 99.0;  // nearest rank 99 of 100: 990 DN above black
    const double range = 4031.0, k = system_gain(s);
    EXPECT_NEAR(meter_exposure(ae, s, raw, k).level, 990.0 / range, 1e-12);
    ae.percentile = 50.0;
    EXPECT_NEAR(meter_exposure(ae, s, raw, k).level, 500.0 / range, 1e-12);
    ae.percentile = 100.0;
    EXPECT_NEAR(meter_exposure(ae, s, raw, k).level, 1000.0 / range, 1e-12);
    ae.metering = Metering::Mean;  // mean of 10, 20, ..., 1000
    EXPECT_NEAR(meter_exposure(ae, s, raw, k).level, 505.0 / range, 1e-12);
    EXPECT_FALSE(meter_exposure(ae, s, raw, k).saturated);
    // Below a gain of range / full_well the full well clips first.
    EXPECT_NEAR(meter_exposure(ae, s, raw, 0.1).clip_level, 1000.0 / range, 1e-12);
    EXPECT_THROW(meter_exposure(ae, s, Image(), k), InputError);
}

/// Half the frame at L, half at 4 L: the percentile meter puts the bright half at the target,
/// the mean meter the mean of both halves (2.5 L): 1.6 times the percentile's exposure.
TEST(AutoExposure, PercentileAndMeanMetersBothSettle) {
    double product[2] = {0.0, 0.0};
    for (Metering meter : {Metering::Percentile, Metering::Mean}) {
        CameraModel m = ae_model(false);
        m.auto_exposure.metering = meter;
        const CameraStage stage(m, pinhole(64, 48, 50.0));
        Image scene = field(stage, 0.05);
        for (int v = 0; v < 24; ++v)
            for (int i = 0; i < 3 * 64; ++i) scene.row(v)[i] *= 4.0f;
        const Sequence r = record(
            stage, [&](int) -> const Image& { return scene; }, 16, first_exposure(m));
        expect_within(r, exposure_limits(m.auto_exposure, m.sensor));
        EXPECT_LE(log_error(r.readings.back(), 0.5), 1e-2) << int(meter);
        const FrameExposure& e = r.exposures.back();
        product[int(meter)] = e.exposure_time_ms * e.system_gain;
    }
    EXPECT_NEAR(product[int(Metering::Mean)] / product[int(Metering::Percentile)], 1.6, 0.02);
}

std::string refusal(const std::function<void(AutoExposure&)>& change) {
    CameraModel m;
    change(m.auto_exposure);
    try {
        validate(m);
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

TEST(AutoExposure, BadSettingsNameTheKey) {
    EXPECT_EQ(refusal([](AutoExposure&) {}), "");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.damping = 0.0; }),
              "camera.auto_exposure.damping: must be in (0, 1], got 0");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.damping = 1.5; }),
              "camera.auto_exposure.damping: must be in (0, 1], got 1.5");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.target = 1.0; }),
              "camera.auto_exposure.target: must be in (0, 1), got 1");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.percentile = 0.0; }),
              "camera.auto_exposure.metering.percentile: must be in (0, 100], got 0");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.min_exposure_time_ms = 0.0; }),
              "camera.auto_exposure.min_exposure_time_ms: must be > 0, got 0");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.max_exposure_time_ms = 0.001; }),
              "camera.auto_exposure.max_exposure_time_ms: must be >= min_exposure_time_ms = "
              "0.01 ms, got 0.001");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.min_system_gain = -1.0; }),
              "camera.auto_exposure.min_system_gain: must be > 0, got -1");
    EXPECT_EQ(refusal([](AutoExposure& a) {
                  a.min_system_gain = 2.0;
                  a.max_system_gain = 1.0;
              }),
              "camera.auto_exposure.max_system_gain: must be >= min_system_gain = 2 DN per "
              "electron, got 1");
    EXPECT_EQ(refusal([](AutoExposure& a) { a.target = std::nan(""); }).substr(0, 27),
              "camera.auto_exposure.target");
}

}  // namespace
}  // namespace deepsea
