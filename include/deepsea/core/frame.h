#pragma once
/// \file One RGB-D frame: the unit of input the runtime, the reference and the scene share.

#include "deepsea/core/image.h"

namespace deepsea {

/// Linear RGB albedo (3 channels) and planar z-depth in metres (1 channel), same size.
struct Frame {
    Image rgb;
    Image depth;
};

}  // namespace deepsea
