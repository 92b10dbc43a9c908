#pragma once
/// \file The Bayer mosaic and its demosaic (docs/bayer.md): which channel a
/// photosite records, and the bilinear interpolation that gives every pixel R, G and B again.

#include <optional>
#include <string>

#include "deepsea/camera/model.h"
#include "deepsea/core/image.h"
#include "deepsea/core/parallel.h"

namespace deepsea {

/// The pattern's name in files: none, rggb, bggr, grbg, gbrg.
const char* bayer_name(BayerPattern p);
/// The pattern of a name (nullopt for an unknown one).
std::optional<BayerPattern> bayer_from_name(const std::string& name);
/// The names, comma-separated, for error messages.
std::string bayer_names();

/// The channel (0 R, 1 G, 2 B) that pixel (u, v) records under pattern p (not None): the
/// 2 x 2 tile's entry (u mod 2, v mod 2).
inline int bayer_channel(BayerPattern p, int u, int v) {
    // Tiles left to right, top to bottom: R G / G B, B G / G R, G R / B G, G B / R G.
    static constexpr int kTile[4][4] = {{0, 1, 1, 2}, {2, 1, 1, 0}, {1, 0, 2, 1}, {1, 2, 0, 1}};
    return kTile[int(p) - 1][2 * (v & 1) + (u & 1)];
}

/// Row v of the bilinear demosaic of a mosaic (3 channels, each pixel's recorded channel holding
/// its value; the others are not read) into dst_rgb (3 x width). Each channel is the normalised
/// convolution of its recorded photosites with [1 2 1; 2 4 2; 1 2 1] (R, B) or [0 1 0; 1 4 1;
/// 0 1 0] (G): a recorded value is kept, a missing one is the mean of its nearest recorded
/// neighbours (2 or 4), and at the image's border the mean of those inside.
void demosaic_row(const Image& mosaic, BayerPattern p, int v, float* dst_rgb);

/// The whole image (dst resized to the mosaic's size), rows in parallel.
void demosaic(const Image& mosaic, BayerPattern p, Image& dst, const Parallel& par = {});

}  // namespace deepsea
