#pragma once
/// \file Camera poses of an RGB-D sequence from a TUM-format trajectory file (`render
/// --poses`, docs/snow-shadows.md "Marine snow"): marine snow stays fixed in the world as the
/// camera moves.

#include <string>
#include <vector>

#include "deepsea/optics/snow.h"

namespace deepsea {

/// One line of a trajectory: its timestamp (seconds, as written) and the camera's pose.
struct TimedPose {
    double timestamp = 0.0;
    CameraPose pose;
};

/// Parses TUM RGB-D trajectory text: one pose a line, `timestamp tx ty tz qx qy qz qw`
/// (camera to world: the camera's centre and the unit quaternion of its orientation, the
/// camera's axes as OpenCV's, x right, y down, z forward), blank lines and lines starting with
/// `#` skipped. InputError "file:line: ..." for a line that is not 8 finite numbers or whose
/// quaternion is not of unit length (within 1e-3; normalised then).
std::vector<TimedPose> parse_tum_poses(const std::string& text, const std::string& file);

/// Reads and parses a trajectory file (IoError if it cannot be read).
std::vector<TimedPose> load_tum_poses(const std::string& path);

}  // namespace deepsea
