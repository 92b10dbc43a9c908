#pragma once
// The bake tests' small setup: a 64x48 camera with an off-centre principal point and fx != fy,
// the asset tests' two lamps, and a lattice small enough that a bake takes milliseconds.

#include "../asset/test_assets.h"
#include "deepsea/bake/bake.h"

namespace deepsea::test {

inline const Camera kBakeCam{64, 48, 50.0, 52.0, 31.5, 23.0};

inline BakeSettings small_bake_settings() {
    BakeSettings s;
    s.step = 8;
    s.depth_samples = 12;
    s.scheme = DepthScheme::Uniform;
    s.z_max = 6.0;
    return s;
}

}  // namespace deepsea::test
