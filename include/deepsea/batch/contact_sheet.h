#pragma once
/// \file A contact sheet: rows of equally sized tiles (e.g. in-air | depth | direct |
/// backscatter | final per frame), for a quick look at a rendered sequence.

#include <vector>

#include "deepsea/core/image.h"

namespace deepsea {

/// Box-filtered copy of a 3-channel image scaled to `width` pixels wide (aspect kept).
Image downscale(const Image& img, int width);

/// Grey 3-channel picture of a depth map: near bright, far dark, open water black
/// (linear values, for sRGB writing).
Image depth_picture(const Image& depth);

/// Tiles (3-channel, linear) laid out row by row with a 4-pixel dark gap; every tile of the
/// sheet is scaled to `tile_width`.
Image contact_sheet(const std::vector<std::vector<Image>>& rows, int tile_width);

}  // namespace deepsea
