// A frame's output is a function of that frame, the asset and the settings only: never of the
// frames a compositor rendered before it (a resumed, sharded or reordered sequence gives the
// same bits as an uninterrupted one).

#include <gtest/gtest.h>

#include "deepsea/bake/bake.h"
#include "deepsea/optics/forward_psf.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "runtime_fixtures.h"

namespace deepsea {

TEST(FrameHistory, AFrameAloneAndAfterADeeperOneAreTheSameBits) {
    const Camera cam = testing::small_camera();
    const Rig rig = testing::two_lamps();
    for (const bool phase_function : {true, false}) {
        Water water = jerlov_water("IB");
        water.forward =
            phase_function ? phase_function_forward_scatter() : default_forward_scatter(water);
        water.forward.enabled = true;
        BakeSettings s;
        s.step = 8;
        s.depth_samples = 8;
        const Asset asset = bake(cam, rig, water, s);
        const AnalyticLamps lamps(rig, water);
        const AssetBackscatter bs(asset, cam);
        const testing::PlaneScene near = testing::plane_scene(cam, 2.0);
        // Deeper than near's farthest surface by far: its distance table spans more.
        const testing::PlaneScene deep = testing::plane_scene(cam, 40.0, 0.0);
        const Frame a{near.rgb, near.depth}, b{deep.rgb, deep.depth};

        Layers alone, after;
        Compositor(cam, water, lamps, bs).composite(alone, a);
        Compositor comp(cam, water, lamps, bs);
        comp.composite(after, b);
        comp.composite(after, a);
        for (const auto& [x, y] : {std::pair{&alone.final, &after.final},
                                   {&alone.forward, &after.forward},
                                   {&alone.direct, &after.direct}}) {
            ASSERT_EQ(x->data.size(), y->data.size());
            std::size_t differ = 0;
            for (std::size_t i = 0; i < x->data.size(); ++i) differ += x->data[i] != y->data[i];
            EXPECT_EQ(differ, 0u) << (phase_function ? "phase function" : "Jaffe-McGlamery");
        }
        EXPECT_GT(alone.forward.at(60, 45, 1), 0.0f);  // forward scatter is there to differ
        // And back: the deeper frame after the near one is its own bits too.
        Layers deep_alone, deep_after;
        Compositor(cam, water, lamps, bs).composite(deep_alone, b);
        comp.composite(deep_after, b);
        EXPECT_EQ(deep_alone.final.data, deep_after.final.data);
    }
}

}  // namespace deepsea
