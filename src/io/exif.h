#pragma once
// EXIF orientation of a JPEG (private to deepsea_io). deepsea pairs colour and depth pixel by
// pixel as they are stored; a viewer shows a JPEG tagged with another orientation rotated or
// mirrored, and its colour would meet the depth turned. Such a file is refused, not turned: the
// tag says how to show the picture, not how the depth image beside it was stored.

#include <cstddef>
#include <cstdint>
#include <string>

namespace deepsea::io_detail {

/// The EXIF orientation (1 to 8; 1 is upright) of the JPEG in bytes [data, data + size), read
/// from its first APP1 "Exif" segment before the image data. 1 if there is no such tag, or the
/// segment is damaged (the decoder reports damage in the image itself).
int jpeg_orientation(const std::uint8_t* data, std::size_t size);

/// What an orientation value means, in words: "rotated 180 degrees", "mirrored left-right", ...
std::string describe_orientation(int orientation);

}  // namespace deepsea::io_detail
