#include "manifest_writer.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <mutex>
#include <thread>
#include <vector>

#include "deepsea/core/error.h"

namespace deepsea {

namespace {

SequenceManifest done(int frames) {
    SequenceManifest m;
    m.frames_total = 1000;
    m.frames_done = frames;
    return m;
}

/// What a writer was given, in order, from its thread and write_now's.
struct Log {
    std::mutex mutex;
    std::vector<int> written;
    void add(const SequenceManifest& m) {
        std::lock_guard<std::mutex> lock(mutex);
        written.push_back(m.frames_done);
    }
};

}  // namespace

// Frames that finish while a write is in flight are covered by the next write: fewer writes
// than frames, each newer than the one before, the last the final count.
TEST(ManifestWriter, CoalescesFramesFinishedDuringAWriteAndNeverGoesBack) {
    Log log;
    {
        ManifestWriter w([&](const SequenceManifest& m) {
            std::this_thread::sleep_for(std::chrono::milliseconds(2));  // an fsync
            log.add(m);
        });
        for (int i = 1; i <= 200; ++i) {
            w.post(done(i));
            if (i % 20 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(3));
        }
        w.write_now(done(200));
    }
    ASSERT_FALSE(log.written.empty());
    EXPECT_LT(log.written.size(), 100u);
    EXPECT_EQ(log.written.back(), 200);
    for (std::size_t i = 1; i < log.written.size(); ++i)
        EXPECT_LE(log.written[i - 1], log.written[i]) << "write " << i << " went back";
}

// post returns while a write is in flight (the pipeline's lock is held around it).
TEST(ManifestWriter, PostDoesNotWaitForTheWriteInFlight) {
    std::promise<void> entered, release;
    std::shared_future<void> gate = release.get_future().share();
    bool first = true;
    Log log;
    ManifestWriter w([&](const SequenceManifest& m) {
        if (first) {
            first = false;
            entered.set_value();
            gate.wait();
        }
        log.add(m);
    });
    w.post(done(1));
    entered.get_future().wait();  // the thread is inside the first write
    auto posting = std::async(std::launch::async, [&] {
        for (int i = 2; i <= 50; ++i) w.post(done(i));
    });
    EXPECT_EQ(posting.wait_for(std::chrono::seconds(20)), std::future_status::ready);
    release.set_value();
    w.write_now(done(50));
    EXPECT_EQ(log.written.front(), 1);
    EXPECT_EQ(log.written.back(), 50);
    EXPECT_LE(log.written.size(), 3u);  // 1, then 50 posted (coalesced), then the final 50
}

// A manifest that cannot be written stops the render: the next post or write_now throws it.
TEST(ManifestWriter, AFailedWriteIsThrownByTheNextCall) {
    ManifestWriter w([](const SequenceManifest&) { throw IoError("m.json: write failed"); });
    w.post(done(1));
    bool thrown = false;
    for (int i = 2; i < 10000 && !thrown; ++i) {
        try {
            w.post(done(i));
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        } catch (const IoError& e) {
            EXPECT_STREQ(e.what(), "m.json: write failed");
            thrown = true;
        }
    }
    EXPECT_TRUE(thrown);
    EXPECT_THROW(w.write_now(done(3)), IoError);
}

// The destructor (a render that ends in an exception) still writes what was posted.
TEST(ManifestWriter, TheDestructorWritesWhatWasPosted) {
    Log log;
    {
        ManifestWriter w([&](const SequenceManifest& m) { log.add(m); });
        w.write_now(done(0));
        w.post(done(7));
    }
    EXPECT_EQ(log.written.back(), 7);
}

// Without manifests (the bench, one-frame renders) nothing is written and no thread runs.
TEST(ManifestWriter, NoPathsNoWrites) {
    ManifestWriter w(std::vector<std::string>{});
    w.post(done(1));
    w.write_now(done(1));
}

}  // namespace deepsea
