#pragma once
/// \file A robot middleware's image message (ROS 1 and ROS 2 sensor_msgs/Image have the same
/// fields) as frame views the Renderer reads where they lie, with every field checked: a
/// malformed message is refused with one line naming the topic and the reason, never read out
/// of bounds. No middleware headers: the ROS 1 node and a ROS 2 port fill ImageMessage from
/// their own message type.

#include <cstddef>
#include <cstdint>
#include <string>

#include "deepsea/runtime/frame_view.h"

namespace deepsea {

/// The fields of sensor_msgs/Image, borrowed (the message must outlive the views made of it).
struct ImageMessage {
    std::string encoding;      ///< e.g. rgb8, bgr8, rgba8, bgra8, rgb16, 32FC1, 16UC1
    std::uint32_t width = 0;   ///< pixels
    std::uint32_t height = 0;  ///< pixels
    std::uint32_t step = 0;    ///< bytes from one row to the next
    bool big_endian = false;   ///< is_bigendian
    const std::uint8_t* data = nullptr;
    std::size_t size = 0;          ///< bytes in data
    const char* topic = "colour";  ///< what errors and the views name (must outlive them)
};

/// Colour encodings taken: rgb8, bgr8, rgba8, bgra8 (8-bit sRGB codes; alpha skipped), rgb16,
/// bgr16, rgba16 (16-bit sRGB codes, host byte order).
/// InputError "<topic>: <reason>" for another encoding, an empty image, a step shorter than a
/// row, data that does not hold step x height bytes, big-endian 16-bit samples on this
/// little-endian host, or a size deepsea does not take.
ColorView color_view(const ImageMessage& msg);

/// Depth encodings taken (REP 118): 32FC1 (planar z in metres; NaN, inf and <= 0 are open
/// water) and 16UC1 (millimetres, 0 = no reading, i.e. open water; `mm_scale` metres per unit).
/// InputError "<topic>: <reason>" as color_view, also for a step that is not a whole number of
/// samples.
DepthView depth_view(const ImageMessage& msg, double mm_scale = 0.001);

/// InputError "<colour topic> is WxH but <depth topic> is WxH" when the two differ in size.
void check_same_size(const ColorView& color, const DepthView& depth);

}  // namespace deepsea
