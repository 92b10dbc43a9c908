#include "deepsea/core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace deepsea {

namespace {

/// How often parallel_for visited each of n items.
std::vector<int> visits(std::size_t n, const Parallel& par) {
    std::vector<std::atomic<int>> seen(n);
    parallel_for(
        n,
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t i = begin; i < end; ++i) ++seen[i];
        },
        par);
    return {seen.begin(), seen.end()};
}

}  // namespace

TEST(ParallelFor, CoversEveryItemOnceAtOneAndTwoThreads) {
    for (const int threads : {1, 2, 0}) {
        for (const std::size_t grain : {0, 1, 7, 1000}) {
            const std::vector<int> seen = visits(997, {threads, grain, {}});
            EXPECT_EQ(seen, std::vector<int>(997, 1)) << threads << " threads, grain " << grain;
        }
    }
    EXPECT_TRUE(visits(0, {2, 1, {}}).empty());
}

TEST(ParallelFor, SubRangesRespectTheGrain) {
    std::atomic<std::size_t> largest{0};
    parallel_for(
        1000,
        [&](std::size_t begin, std::size_t end) {
            std::size_t seen = largest.load();
            while (end - begin > seen && !largest.compare_exchange_weak(seen, end - begin)) {
            }
        },
        {2, 16, {}});
    EXPECT_LE(largest.load(), 16u);
}

TEST(ParallelFor, ProgressCountsAreNonDecreasingAndReachTheTotal) {
    for (const int threads : {1, 2}) {
        std::vector<long> seen;  // the callback runs one call at a time
        long total_seen = 0;
        const Parallel par{threads, 3, [&](long done, long total) {
                               seen.push_back(done);
                               total_seen = total;
                               return true;
                           }};
        visits(200, par);
        ASSERT_FALSE(seen.empty());
        for (std::size_t i = 1; i < seen.size(); ++i) EXPECT_LE(seen[i - 1], seen[i]);
        EXPECT_EQ(seen.back(), 200);
        EXPECT_EQ(total_seen, 200);
    }
}

TEST(ParallelFor, CancelThrowsCancelledAndStopsEarly) {
    for (const int threads : {1, 2}) {
        std::atomic<long> items{0};
        const Parallel par{threads, 1, [](long done, long) { return done < 10; }};
        EXPECT_THROW(parallel_for(
                         100000, [&](std::size_t b, std::size_t e) { items += long(e - b); }, par),
                     Cancelled);
        // Each worker finishes at most the item it holds after the request.
        EXPECT_LT(items.load(), 10 + 2 * threads) << threads << " threads";
    }
}

TEST(ParallelFor, CancelledIsAnErrorWithItsOwnExitCode) {
    const Cancelled c("stopped");
    const Error& e = c;
    EXPECT_EQ(e.exit_code(), 130);
}

TEST(ParallelFor, ExceptionsFromTheBodyPropagate) {
    EXPECT_THROW(parallel_for(100,
                              [](std::size_t b, std::size_t) {
                                  if (b >= 50) throw InputError("bad item");
                              },
                              {2, 1, {}}),
                 InputError);
}

TEST(ParallelFor, NegativeThreadCountIsAConfigError) {
    EXPECT_THROW(parallel_for(10, [](std::size_t, std::size_t) {}, {-1, 0, {}}), ConfigError);
    EXPECT_THROW(in_arena(-1, [] {}), ConfigError);
}

TEST(InArena, RunsTheFunctionOnce) {
    for (const int threads : {0, 1, 2}) {
        int calls = 0;
        in_arena(threads, [&] { ++calls; });
        EXPECT_EQ(calls, 1);
    }
}

TEST(Parallel, OrGrainKeepsTheCallersChoice) {
    EXPECT_EQ(Parallel{}.or_grain(16).grain, 16u);
    EXPECT_EQ((Parallel{2, 4, {}}.or_grain(16).grain), 4u);
    EXPECT_EQ((Parallel{2, 4, {}}.or_grain(16).threads), 2);
}

}  // namespace deepsea
