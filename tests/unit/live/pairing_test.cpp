// Stamp pairing (live/stamp_pairer.h) and the latest-frame slot (live/latest_slot.h): which
// frames pair under each policy, which are dropped and counted, and that a frame arriving while
// one waits replaces it.

#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "deepsea/live/latest_slot.h"
#include "deepsea/live/stamp_pairer.h"

namespace deepsea {

using Pairer = StampPairer<int, int>;  // payloads: the frames' own numbers

TEST(StampPairer, ExactPairsEqualStampsInEitherOrder) {
    Pairer p(PairPolicy::Exact, 1000000);
    EXPECT_FALSE(p.add_color(100, 1));
    auto pair = p.add_depth(100, 2);
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->first, 1);
    EXPECT_EQ(pair->second, 2);
    EXPECT_FALSE(p.add_depth(200, 4));
    pair = p.add_color(200, 3);
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->first, 3);
    EXPECT_EQ(pair->second, 4);
    // a stamp 1 ns off never pairs exactly, whatever the slop
    EXPECT_FALSE(p.add_color(300, 5));
    EXPECT_FALSE(p.add_depth(301, 6));
    EXPECT_EQ(p.unpaired(), 0u);
    EXPECT_EQ(p.waiting(), 2u);
}

TEST(StampPairer, ApproximatePairsTheNearestWithinTheSlop) {
    Pairer p(PairPolicy::Approximate, 10);
    EXPECT_FALSE(p.add_depth(95, 1));
    EXPECT_FALSE(p.add_depth(103, 2));
    EXPECT_FALSE(p.add_color(150, 9));  // 47 ns from the nearest: held
    auto pair = p.add_color(101, 3);    // nearest: 103
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->second, 2);
    // depth 95 was stamped before the pair: it can no longer pair, dropped and counted
    EXPECT_EQ(p.unpaired(), 1u);
    pair = p.add_depth(155, 4);  // colour 150 is within the slop
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->first, 9);
    EXPECT_EQ(p.waiting(), 0u);
}

TEST(StampPairer, FramesOlderThanAPairAndOverflowAreCounted) {
    Pairer p(PairPolicy::Exact, 0, 3);
    for (int i = 0; i < 5; ++i) EXPECT_FALSE(p.add_color(i * 10, i));  // queue of 3: 2 dropped
    EXPECT_EQ(p.unpaired(), 2u);
    auto pair = p.add_depth(40, 40);  // pairs colour 40; colours 20, 30 are older: dropped
    ASSERT_TRUE(pair);
    EXPECT_EQ(pair->first, 4);
    EXPECT_EQ(p.unpaired(), 4u);
    EXPECT_EQ(p.waiting(), 0u);
}

TEST(LatestSlot, AFrameArrivingWhileOneWaitsReplacesIt) {
    LatestSlot<int> slot;
    EXPECT_FALSE(slot.put(1));
    EXPECT_TRUE(slot.put(2));
    EXPECT_TRUE(slot.put(3));
    EXPECT_EQ(slot.replaced(), 2u);
    EXPECT_EQ(slot.take(), 3);
    EXPECT_FALSE(slot.put(4));  // nothing waited
    EXPECT_EQ(slot.take(), 4);
    EXPECT_EQ(slot.replaced(), 2u);
}

TEST(LatestSlot, TakeWaitsForAFrameAndCloseEndsIt) {
    LatestSlot<int> slot;
    std::atomic<int> got{0};
    std::thread consumer([&] {
        while (auto v = slot.take()) got += *v;
    });
    slot.put(5);
    while (got.load() != 5) std::this_thread::yield();
    slot.close();
    consumer.join();
    EXPECT_EQ(got.load(), 5);
    EXPECT_FALSE(slot.take());
}

}  // namespace deepsea
