#pragma once
/// \file Depth formats read without OpenImageIO: PFM and NumPy .npy, parsed by hand so that
/// row order and byte order are ours to get right. read_depth (image_io.h) dispatches to them
/// by extension; they are public for tools and tests that know the format.

#include <string>

#include "deepsea/core/image.h"

namespace deepsea {

/// A PFM image ("Pf": 1 channel, "PF": 3 channels), float values as stored, rows flipped to
/// top-to-bottom (PFM stores the bottom row first); the sign of the scale gives the byte
/// order. Throws IoError for a missing, foreign or truncated file.
Image read_pfm(const std::string& path);

/// A 2-D .npy array (format versions 1-3) as one-channel depth: dtype <f4 or <f8 as stored,
/// <u2 times `scale` (metres per unit); shape (H, W) or (H, W, 1), C or Fortran order.
/// Throws InputError for another dtype or shape, IoError for a missing or truncated file.
Image read_npy(const std::string& path, double scale);

}  // namespace deepsea
