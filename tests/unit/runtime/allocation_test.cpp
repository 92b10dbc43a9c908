// "No allocation per frame after the first" (docs/runtime.md), counted: this test binary
// replaces the global operator new with one that counts calls, then composites frames of one
// size: on one thread none after the first allocates; on all threads only each worker's first
// rows do.

#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <tbb/info.h>

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
        const char* what = set == LayerSet::All ? "all layers" : "final";
        {
            // One thread: after the first frame nothing at all.
            tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
            Layers out;
            comp.composite(out, frame, set);
            const long before = g_news.load();
            for (int i = 0; i < 5; ++i) comp.composite(out, frame, set);
            EXPECT_EQ(g_news.load() - before, 0) << what;
        }
        // All threads: a worker sizes its own row buffers the first time it gets rows (in the
        // row pass, the blur blend, the lookup slice), which on a busy machine may be frames
        // later; after that it allocates nothing. So over 30 frames at most three allocating
        // frames per thread, whatever the load.
        Layers out;
        comp.composite(out, frame, set);
        int allocating = 0;
        for (int i = 0; i < 30; ++i) {
            const long before = g_news.load();
            comp.composite(out, frame, set);
            if (g_news.load() != before) ++allocating;
        }
        EXPECT_LE(allocating, 3 * tbb::info::default_concurrency()) << what;
    }
}

}  // namespace
}  // namespace deepsea
