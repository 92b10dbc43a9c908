// Frames' poses from a trajectory (batch/frame_poses.h): frames named by their timestamps take
// the pose at their time (interpolated between the trajectory's poses, the nearest at its
// ends, none beyond the tolerance: one line naming the frame and the file), other frames the
// n-th pose; with motion streaks each frame's shutter is the constant-velocity pose half an
// exposure either side of its time.

#include "deepsea/batch/frame_poses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

/// A camera moving at constant linear and angular velocity: its pose at time t.
CameraPose motion(double t) {
    const Vec3 axis = normalize(Vec3{0.2, 1.0, -0.3});
    const double a = 0.5 * t;  // rad
    const auto rot = [&](const Vec3& v) {
        return v * std::cos(a) + cross(axis, v) * std::sin(a) +
               axis * (dot(axis, v) * (1 - std::cos(a)));
    };
    return {Vec3{0.3, -0.1, 0.05} * t + Vec3{1, 2, 3}, rot({1, 0, 0}), rot({0, 1, 0}),
            rot({0, 0, 1})};
}

void expect_pose(const CameraPose& a, const CameraPose& b, double tol) {
    for (const auto& [x, y] : {std::pair{a.origin, b.origin}, std::pair{a.right, b.right},
                               std::pair{a.down, b.down}, std::pair{a.forward, b.forward}})
        EXPECT_LE(length(x - y), tol);
}

/// A trajectory sampled every `step` seconds from t0 to t1, timestamps as written.
std::vector<TimedPose> trajectory(double t0, double t1, double step) {
    std::vector<TimedPose> out;
    for (double t = t0; t <= t1 + 1e-9; t += step) out.push_back({t, motion(t)});
    return out;
}

std::vector<FrameJob> frames(const std::vector<std::string>& names) {
    std::vector<FrameJob> jobs;
    for (const std::string& n : names)
        jobs.push_back(FrameJob{"rgb/" + n, "depth/" + n, "", "x", {}, {}});
    return jobs;
}

SnowSettings streaks(double exposure_s, double rate = 0.0) {
    SnowSettings s;
    s.snow = snow_preset("abyssal");
    s.streaks = true;
    s.exposure_time_s = exposure_s;
    s.frame_rate_hz = rate;
    return s;
}

}  // namespace

TEST(FramePoses, StemTimestamps) {
    EXPECT_DOUBLE_EQ(*stem_timestamp("rgb/1305031102.175304.png"), 1305031102.175304);
    EXPECT_DOUBLE_EQ(*stem_timestamp("0.5.exr"), 0.5);
    for (const char* name : {"0001.png", "frame_1.5.png", "1..png", ".5.png", "1.5e3.png", "a/b"})
        EXPECT_FALSE(stem_timestamp(name)) << name;
}

TEST(FramePoses, PoseAtTimeInterpolatesWithinTheTolerance) {
    // 100 Hz, as TUM RGB-D's ground truth; times far from zero, as its Unix timestamps.
    const double t0 = 1305031102.0;
    const auto poses = trajectory(t0, t0 + 1.0, 0.01);
    for (const double dt : {0.0, 0.0123, 0.5, 0.99})
        expect_pose(*pose_at_time(poses, t0 + dt), motion(t0 + dt), 2e-6);
    // Past the ends: the nearest pose within the tolerance, none beyond it.
    expect_pose(*pose_at_time(poses, t0 + 1.0 + 0.015), poses.back().pose, 1e-12);
    EXPECT_FALSE(pose_at_time(poses, t0 + 1.0 + 0.025));
    EXPECT_FALSE(pose_at_time(poses, t0 - 0.021));
    // A gap in the trajectory wider than twice the tolerance: the nearest within it, else none.
    std::vector<TimedPose> gap = {{0.0, motion(0.0)}, {0.1, motion(0.1)}};
    expect_pose(*pose_at_time(gap, 0.015), motion(0.0), 1e-12);
    expect_pose(*pose_at_time(gap, 0.09), motion(0.1), 1e-12);
    EXPECT_FALSE(pose_at_time(gap, 0.05));
}

TEST(FramePoses, FramesNamedByTimeTakeThePoseAtTheirTime) {
    auto poses = trajectory(100.0, 101.0, 0.01);
    std::swap(poses[3], poses[40]);  // any order in the file
    std::vector<FrameJob> jobs = frames({"100.200000.png", "100.233333.png", "100.266667.png"});
    const SnowSettings s = streaks(0.02);
    EXPECT_EQ(assign_poses(jobs, poses, "gt.txt", s), PoseMatch::Timestamp);
    for (const double t : {100.2, 100.233333, 100.266667}) {
        const FrameJob& j = jobs[std::size_t(std::lround((t - 100.2) * 30))];
        expect_pose(*j.pose, motion(t), 1e-6);
        // The shutter: half the exposure either side of the frame's time.
        expect_pose(j.shutter->open, motion(t - 0.01), 1e-6);
        expect_pose(j.shutter->close, motion(t + 0.01), 1e-6);
    }
    // A frame beyond the trajectory: one line naming the frame and the file.
    std::vector<FrameJob> late = frames({"100.200000.png", "101.500000.png"});
    try {
        assign_poses(late, poses, "gt.txt", std::nullopt);
        FAIL() << "no error";
    } catch (const InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("gt.txt"), std::string::npos) << m;
        EXPECT_NE(m.find("rgb/101.500000.png"), std::string::npos) << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

TEST(FramePoses, OtherFramesTakeTheNthPose) {
    // Timestamps that increase: the frame interval comes from them.
    std::vector<TimedPose> poses = {{0.0, motion(0.0)}, {0.05, motion(0.05)}, {0.1, motion(0.1)}};
    std::vector<FrameJob> jobs = frames({"0001.png", "0002.png", "0003.png"});
    EXPECT_EQ(assign_poses(jobs, poses, "p.txt", streaks(0.01)), PoseMatch::Order);
    for (int i = 0; i < 3; ++i) {
        expect_pose(*jobs[std::size_t(i)].pose, poses[std::size_t(i)].pose, 0.0);
        expect_pose(jobs[std::size_t(i)].shutter->open, motion(0.05 * i - 0.005), 1e-9);
        expect_pose(jobs[std::size_t(i)].shutter->close, motion(0.05 * i + 0.005), 1e-9);
    }
    // Without streaks, no shutter.
    std::vector<FrameJob> plain = frames({"0001.png", "0002.png", "0003.png"});
    assign_poses(plain, poses, "p.txt", std::nullopt);
    EXPECT_FALSE(plain[1].shutter);
    // Timestamps that do not increase: the frame rate, or one line asking for it.
    for (TimedPose& p : poses) p.timestamp = 0.0;
    std::vector<FrameJob> rated = frames({"0001.png", "0002.png", "0003.png"});
    assign_poses(rated, {{0, motion(0)}, {0, motion(0.1)}, {0, motion(0.2)}}, "p.txt",
                 streaks(0.02, 10.0));
    expect_pose(rated[2].shutter->open, motion(0.19), 1e-9);
    try {
        assign_poses(rated, poses, "p.txt", streaks(0.02));
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("p.txt"), std::string::npos) << m;
        EXPECT_NE(m.find("snow.frame_rate_hz"), std::string::npos) << m;
    }
    // A count that differs: one line naming the file.
    std::vector<FrameJob> two = frames({"0001.png", "0002.png"});
    EXPECT_THROW(assign_poses(two, poses, "p.txt", std::nullopt), InputError);
}

}  // namespace deepsea
