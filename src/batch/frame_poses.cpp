#include "deepsea/batch/frame_poses.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "deepsea/core/error.h"
#include "deepsea/optics/camera_motion.h"

namespace deepsea {

namespace {

std::string seconds(double t) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6f", t);
    return buf;
}

}  // namespace

std::optional<double> stem_timestamp(const std::string& path) {
    const std::string s = std::filesystem::path(path).stem().string();
    const auto point = s.find('.');
    const auto digits = [&](std::size_t a, std::size_t b) {
        return b > a && std::all_of(s.begin() + long(a), s.begin() + long(b),
                                    [](char c) { return c >= '0' && c <= '9'; });
    };
    if (point == std::string::npos || !digits(0, point) || !digits(point + 1, s.size()))
        return std::nullopt;
    return std::stod(s);
}

std::optional<CameraPose> pose_at_time(const std::vector<TimedPose>& poses, double t,
                                       double tolerance) {
    const auto after =
        std::lower_bound(poses.begin(), poses.end(), t,
                         [](const TimedPose& p, double x) { return p.timestamp < x; });
    const bool has_after = after != poses.end(), has_before = after != poses.begin();
    const double da = has_after ? after->timestamp - t : INFINITY;
    const double db = has_before ? t - std::prev(after)->timestamp : INFINITY;
    if (da == 0.0) return after->pose;
    if (da <= tolerance && db <= tolerance) {
        const TimedPose& b = *std::prev(after);
        return interpolate_pose(b.pose, after->pose, db / (after->timestamp - b.timestamp));
    }
    if (std::min(da, db) > tolerance) return std::nullopt;
    return da < db ? after->pose : std::prev(after)->pose;
}

PoseMatch assign_poses(std::vector<FrameJob>& jobs, std::vector<TimedPose> poses,
                       const std::string& file, const std::optional<SnowSettings>& snow) {
    std::vector<std::optional<double>> stamps;
    for (const FrameJob& j : jobs) stamps.push_back(stem_timestamp(j.rgb));
    const bool by_time =
        !jobs.empty() && std::all_of(stamps.begin(), stamps.end(), [](auto s) { return s; });
    std::vector<double> times(jobs.size(), 0.0);
    bool timed = true;  // times[] holds each frame's time
    if (by_time) {
        std::stable_sort(poses.begin(), poses.end(), [](const TimedPose& a, const TimedPose& b) {
            return a.timestamp < b.timestamp;
        });
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            times[i] = *stamps[i];
            const auto p = pose_at_time(poses, times[i]);
            if (!p)
                throw InputError(file + ": no pose within " + seconds(kPoseTimeTolerance) +
                                 " s of frame " + jobs[i].rgb + " (its name gives the time " +
                                 seconds(times[i]) + " s; poses from " +
                                 seconds(poses.front().timestamp) + " to " +
                                 seconds(poses.back().timestamp) + " s)");
            jobs[i].pose = p;
        }
    } else {
        if (poses.size() != jobs.size())
            throw InputError(file + ": " + std::to_string(poses.size()) + " pose(s) for " +
                             std::to_string(jobs.size()) +
                             " frame(s); give one pose a frame, in frame order (or name the "
                             "frames by their timestamps to match them by time)");
        for (std::size_t i = 0; i < jobs.size(); ++i) {
            jobs[i].pose = poses[i].pose;
            times[i] = poses[i].timestamp;
            if (i > 0 && !(times[i] > times[i - 1])) timed = false;
        }
    }
    if (!snow || !snow->streaks || jobs.size() < 2)
        return by_time ? PoseMatch::Timestamp : PoseMatch::Order;
    if (!timed) {
        if (!(snow->frame_rate_hz > 0.0))
            throw ConfigError(file +
                              ": the timestamps do not increase from frame to frame, so they "
                              "give the motion streaks no frame interval; give "
                              "snow.frame_rate_hz");
        for (std::size_t i = 0; i < jobs.size(); ++i) times[i] = double(i) / snow->frame_rate_hz;
    }
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        const std::size_t o = i + 1 < jobs.size() ? i + 1 : i - 1;
        if (times[o] == times[i])
            throw InputError(file + ": frames " + jobs[i].rgb + " and " + jobs[o].rgb +
                             " have the same time, " + seconds(times[i]) +
                             " s: no frame interval for the motion streaks");
        jobs[i].shutter =
            shutter_poses(*jobs[i].pose, times[i], *jobs[o].pose, times[o], snow->exposure_time_s);
    }
    return by_time ? PoseMatch::Timestamp : PoseMatch::Order;
}

}  // namespace deepsea
