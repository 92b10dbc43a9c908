#pragma once
// The ROS 1 side of deepsea_ros and deepsea_rosbag: sensor_msgs to and from the live core
// (deepsea/live), and the settings both read. Everything else lives in the core, which a
// ROS 2 port calls unchanged (docs/ros.md).

#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <optional>
#include <string>

#include "deepsea/live/image_message.h"
#include "deepsea/live/live_renderer.h"
#include "deepsea/live/stamp_pairer.h"

namespace deepsea::ros1 {

/// The fields of `msg`, borrowed; `topic` names it in errors (must outlive the views).
ImageMessage fields(const sensor_msgs::Image& msg, const char* topic);

/// An image message of a rendered buffer (`bytes`, packed rows) with `header`.
sensor_msgs::ImagePtr image_message(const std_msgs::Header& header, int width, int height,
                                    const std::string& encoding, const void* bytes,
                                    std::size_t sample_bytes);

/// The camera_info of the frames' pinhole camera (no distortion), with `header`.
sensor_msgs::CameraInfoPtr camera_info(const std_msgs::Header& header, const Camera& camera);

/// The pinhole camera a camera_info describes (K and the size).
Camera camera_of(const sensor_msgs::CameraInfo& info);

/// What both tools read (ROS parameters, command-line flags); docs/ros.md lists them.
struct Options {
    std::string asset;        ///< the baked asset (.vdb), required
    std::string camera_yaml;  ///< setup YAML: camera section (intrinsics, lens, sensor,
                              ///< processing, port) and snow section; optional
    std::string exposure = "auto";
    bool forward = true, shadows = false;
    std::string snow;  ///< a preset, "off", or "" (the camera YAML's, else none)
    int snow_seed = 1;
    bool backscatter = false, noise_free = false, depth = false;
    double depth_scale = 0.001;  ///< metres per 16UC1 unit
    std::string sync = "exact";  ///< or "approximate"
    double slop = 0.01;          ///< seconds, approximate sync
    int queue = 8;               ///< unpaired frames held per stream
};

/// The core's settings for `o` (reads the camera YAML through io's strict reader): ConfigError
/// naming the option or the YAML's file, line and key.
LiveSettings live_settings(const Options& o);

/// The sync policy: ConfigError for a name other than exact or approximate.
PairPolicy pair_policy(const Options& o);

}  // namespace deepsea::ros1
