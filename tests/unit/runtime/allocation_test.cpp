// "No allocation per frame after the first" (DESIGN.md section 4), counted: this test binary
// replaces the global operator new with one that counts calls, then composites frames of one
// size and checks that none after the warm-up allocated.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "deepsea/bake/bake.h"
#include "deepsea/runtime/asset_backscatter.h"
#include "deepsea/runtime/compositor.h"
#include "deepsea/runtime/lamps.h"
#include "runtime_fixtures.h"

namespace {
std::atomic<long> g_news{0};
}  // namespace

void* operator new(std::size_t n) {
    g_news.fetch_add(1, std::memory_order_relaxed);
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace deepsea {
namespace {

TEST(Compositor, AllocatesNothingAfterTheFirstFrames) {
    const Camera cam = testing::small_camera();
    const Rig rig = testing::two_lamps();
    const Water water = testing::ib_with_forward();
    const testing::PlaneScene scene = testing::plane_scene(cam);
    BakeSettings settings;
    settings.step = 8;
    const Asset asset = bake(cam, rig, water, settings);
    const AnalyticLamps lamps(rig, water);
    const AssetBackscatter bs(asset, cam);
    Compositor comp(cam, water, lamps, bs);
    const Frame frame{scene.rgb, scene.depth};
    for (LayerSet set : {LayerSet::All, LayerSet::Final}) {
        Layers out;
        // Warm-up: buffers grow, and each worker thread sizes its own row scratch.
        for (int i = 0; i < 8; ++i) comp.composite(out, frame, set);
        const long before = g_news.load();
        for (int i = 0; i < 5; ++i) comp.composite(out, frame, set);
        EXPECT_EQ(g_news.load() - before, 0) << (set == LayerSet::All ? "all layers" : "final");
    }
}

}  // namespace
}  // namespace deepsea
