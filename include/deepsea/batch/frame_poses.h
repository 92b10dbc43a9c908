#pragma once
/// \file The frames' camera poses from a trajectory (`render --poses`, docs/snow-shadows.md,
/// "Marine snow" and "Motion streaks"): matched by timestamp where the frames are named by
/// their time, else in order; with motion streaks, each frame's shutter poses.

#include <optional>
#include <string>
#include <vector>

#include "deepsea/batch/frame_jobs.h"
#include "deepsea/io/poses.h"
#include "deepsea/runtime/marine_snow.h"

namespace deepsea {

/// How far (seconds) a frame's time may lie from the trajectory's poses: TUM RGB-D's
/// associate.py default (max_difference 0.02 s).
inline constexpr double kPoseTimeTolerance = 0.02;

/// A frame's time from its colour file's stem where the stem is a timestamp as TUM RGB-D writes
/// them, digits, a point and digits (1305031102.175304); unset otherwise (0001, frame_12).
std::optional<double> stem_timestamp(const std::string& path);

/// The pose at time t of a trajectory sorted by time: interpolated (centre lerp, orientation
/// slerp, camera_motion.h) between the poses just before and after t where both lie within
/// `tolerance` seconds of it, else the nearest within `tolerance`; unset where none is.
std::optional<CameraPose> pose_at_time(const std::vector<TimedPose>& poses, double t,
                                       double tolerance = kPoseTimeTolerance);

/// How assign_poses matched frames and poses.
enum class PoseMatch { Order, Timestamp };

/// Gives each job its pose from the trajectory `poses` read from `file`:
/// - by timestamp (pose_at_time) when every frame's colour stem is a timestamp
///   (stem_timestamp): InputError naming the frame and `file` for a frame with no pose within
///   kPoseTimeTolerance;
/// - else the n-th pose to the n-th frame: InputError naming `file` unless there are as many
///   poses as frames.
/// With `snow` streaks on and two frames or more, each frame's shutter too (shutter_poses over
/// the snow's exposure time, the camera's velocity that of the move to the next frame, the
/// last frame's from the previous one). A frame's time is its stem's timestamp, else its
/// pose's timestamp where the trajectory's increase from frame to frame, else its index over
/// snow.frame_rate_hz: ConfigError naming `file` and snow.frame_rate_hz when none applies.
PoseMatch assign_poses(std::vector<FrameJob>& jobs, std::vector<TimedPose> poses,
                       const std::string& file, const std::optional<SnowSettings>& snow);

}  // namespace deepsea
