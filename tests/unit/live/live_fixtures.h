#pragma once
// Shared fixtures of the live tests: a small baked asset and an RGB-D frame as message bytes.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "deepsea/bake/bake.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/optics/light.h"

namespace deepsea::testing {

inline Camera live_camera() { return Camera{120, 90, 90.0, 90.0, 59.5, 44.5}; }

inline const Asset& live_asset() {
    static const Asset asset = [] {
        Rig rig;
        for (int s : {-1, 1}) {
            Light l;
            l.position = {0.5 * s, 0.0, 0.0};
            l.direction = normalize(Vec3(-s * std::sin(0.5), 0.0, std::cos(0.5)));
            l.intensity = {1.0, 0.9, 0.8};
            rig.lights.push_back(l);
        }
        BakeSettings b;
        b.step = 8;
        b.depth_samples = 8;
        return bake(live_camera(), rig, jerlov_water("IB"), b);
    }();
    return asset;
}

/// A tilted plane with a checker albedo: rgb8 codes and 32FC1 depth bytes, packed.
struct Rgbd {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb8, depth32;
};

inline Rgbd live_frame(int w, int h, float shade = 1.0f) {
    Rgbd f{w, h, std::vector<std::uint8_t>(3 * w * h), std::vector<std::uint8_t>(4 * w * h)};
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) {
            const int i = v * w + u;
            const float z = 2.0f + 1.5f * float(v) / float(h);
            std::memcpy(&f.depth32[4 * i], &z, 4);
            const int checker = ((u * 8 / w) + (v * 8 / h)) % 2;
            f.rgb8[3 * i + 0] = std::uint8_t(shade * (checker ? 200 : 60));
            f.rgb8[3 * i + 1] = std::uint8_t(shade * 150);
            f.rgb8[3 * i + 2] = std::uint8_t(shade * (40 + u % 100));
        }
    return f;
}

}  // namespace deepsea::testing
