#include "deepsea/batch/sequence.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "../runtime/runtime_fixtures.h"
#include "deepsea/bake/bake.h"
#include "deepsea/batch/frame_files.h"
#include "deepsea/batch/sequence_manifest.h"
#include "deepsea/core/error.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

struct SequenceDir {
    fs::path dir;
    Asset asset;
    std::vector<FrameJob> jobs;

    explicit SequenceDir(const std::string& name, int frames = 3) {
        dir = fs::temp_directory_path() / ("deepsea-seq-" + name + "-" + std::to_string(getpid()));
        fs::remove_all(dir);
        fs::create_directories(dir / "out");
        const Camera cam = testing::small_camera();
        BakeSettings s;
        s.step = 8;
        s.depth_samples = 8;
        asset = bake(cam, testing::two_lamps(), jerlov_water("IB"), s);
        const testing::PlaneScene scene = testing::plane_scene(cam);
        for (int i = 0; i < frames; ++i) {
            FrameJob j;
            j.rgb = (dir / ("f" + std::to_string(i) + ".png")).string();
            j.depth = (dir / ("f" + std::to_string(i) + "_depth.exr")).string();
            j.output = (dir / "out" / ("f" + std::to_string(i) + ".png")).string();
            write_color(j.rgb, scene.rgb);
            write_depth_exr(j.depth, scene.depth);
            jobs.push_back(j);
        }
    }
    ~SequenceDir() { fs::remove_all(dir); }
};

}  // namespace

TEST(Sequence, WritesEveryFrame) {
    SequenceDir d("all");
    const SequenceResult r = render_sequence(d.asset, d.jobs, SequenceOptions{});
    EXPECT_EQ(r.written, 3);
    EXPECT_TRUE(r.errors.empty());
    for (const auto& j : d.jobs) EXPECT_TRUE(fs::exists(j.output)) << j.output;
    EXPECT_GT(r.exposure, 0.0);
}

// Writers run in parallel and finish out of order (here three PNG frames follow a slow TIFF
// with every layer as EXR):
// every output must still hold its own frame, as a render of that frame alone does.
TEST(Sequence, EveryOutputHoldsItsOwnFrame) {
    const int n = 12;
    SequenceDir d("own", n);
    for (int i = 0; i < n; ++i) {
        Image rgb = read_color(d.jobs[i].rgb);
        for (float& x : rgb.data) x *= 0.2f + 0.06f * float(i);
        write_color(d.jobs[i].rgb, rgb);
        if (i % 4 == 0) {  // slower to write: TIFF, and every layer as EXR
            d.jobs[i].output = (d.dir / "out" / ("f" + std::to_string(i) + ".tif")).string();
            d.jobs[i].layers = (d.dir / "out" / ("f" + std::to_string(i) + ".exr")).string();
        }
    }
    SequenceOptions opt;
    opt.exposure = parse_exposure("40");
    const SequenceResult r = render_sequence(d.asset, d.jobs, opt);
    ASSERT_EQ(r.written, n);
    for (int i = 0; i < n; ++i) {
        FrameJob alone = d.jobs[i];
        alone.output =
            (d.dir / ("alone" + fs::path(d.jobs[i].output).extension().string())).string();
        ASSERT_EQ(render_sequence(d.asset, {alone}, opt).written, 1);
        EXPECT_EQ(read_color(d.jobs[i].output).data, read_color(alone.output).data)
            << "frame " << i << " holds another frame's pixels";
    }
}

TEST(Sequence, CorruptFrameIsReportedAndTheRestWritten) {
    SequenceDir d("corrupt");
    std::ofstream(d.jobs[1].depth, std::ios::trunc) << "not an exr";
    const SequenceResult r = render_sequence(d.asset, d.jobs, SequenceOptions{});
    EXPECT_EQ(r.written, 2);
    ASSERT_EQ(r.errors.size(), 1u);
    EXPECT_NE(r.errors[0].find("f1_depth.exr"), std::string::npos) << r.errors[0];
    EXPECT_FALSE(fs::exists(d.jobs[1].output));
    EXPECT_TRUE(fs::exists(d.jobs[2].output));
}

TEST(Sequence, ResumeSkipsFramesAlreadyWritten) {
    SequenceDir d("resume");
    render_sequence(d.asset, {d.jobs[0]}, SequenceOptions{});
    SequenceOptions opt;
    opt.resume = true;
    const SequenceResult r = render_sequence(d.asset, d.jobs, opt);
    EXPECT_EQ(r.skipped, 1);
    EXPECT_EQ(r.written, 2);
}

TEST(Sequence, UnwritableOutputIsAnErrorPerFrame) {
    SequenceDir d("unwritable", 1);
    d.jobs[0].output = (d.dir / "missing-folder" / "x.png").string();
    const SequenceResult r = render_sequence(d.asset, d.jobs, SequenceOptions{});
    EXPECT_EQ(r.written, 0);
    EXPECT_EQ(r.errors.size(), 1u);
    EXPECT_FALSE(fs::exists(d.jobs[0].output));
}

TEST(Sequence, AssetForAnotherCameraStopsEverything) {
    SequenceDir d("camera", 1);
    SequenceOptions opt;
    opt.camera = testing::small_camera();
    opt.camera.fx *= 1.5;
    EXPECT_THROW(render_sequence(d.asset, d.jobs, opt), AssetError);
}

TEST(Sequence, ManifestKeepsTheExposureForResume) {
    SequenceDir d("manifest");
    SequenceOptions opt;
    opt.manifests = {(d.dir / "out" / kManifestName).string()};
    opt.rgb_pattern = (d.dir / "*.png").string();
    opt.depth_pattern = (d.dir / "*_depth.exr").string();
    opt.version = "test";
    const SequenceResult first = render_sequence(d.asset, d.jobs, opt);
    ASSERT_EQ(first.written, 3);
    SequenceManifest m = read_manifest(opt.manifests[0]);
    EXPECT_EQ(m.exposure, first.exposure);
    EXPECT_EQ(m.frames_done, 3);
    // The folder's exposure wins over what the frame composited first would give.
    m.exposure = 2.0 * first.exposure;
    write_manifest(opt.manifests[0], m);
    fs::remove(d.jobs[2].output);
    opt.resume = true;
    const SequenceResult again = render_sequence(d.asset, d.jobs, opt);
    EXPECT_EQ(again.written, 1);
    EXPECT_EQ(again.skipped, 2);
    EXPECT_EQ(again.exposure, 2.0 * first.exposure);
    // Another asset: refused before any frame is touched.
    Asset other = d.asset;
    other.info.input_hash = "fnv1a64:0000000000000000";
    fs::remove(d.jobs[0].output);
    EXPECT_THROW(render_sequence(other, d.jobs, opt), ConfigError);
    EXPECT_FALSE(fs::exists(d.jobs[0].output));
}

// The manifests are written from a thread of their own as frames finish: at every moment the
// count on disk is one of frames whose outputs are complete, it never goes back, and at the
// end both folders' manifests count every frame and are the same bytes.
TEST(Sequence, ManifestNeverCountsAFrameNotOnDiskAndEndsWithEveryFrame) {
    const int n = 12;
    SequenceDir d("manifest-async", n);
    fs::create_directories(d.dir / "lay");
    for (int i = 0; i < n; ++i)
        d.jobs[i].layers = (d.dir / "lay" / ("f" + std::to_string(i) + ".exr")).string();
    SequenceOptions opt;
    opt.manifests = {(d.dir / "out" / kManifestName).string(),
                     (d.dir / "lay" / kManifestName).string()};
    opt.rgb_pattern = (d.dir / "*.png").string();
    opt.depth_pattern = (d.dir / "*_depth.exr").string();
    opt.version = "test";
    int last = 0, checks = 0;
    opt.on_frame = [&](const FrameJob&, bool) {  // one at a time, after the frame's outputs
        for (const std::string& path : opt.manifests) {
            const int counted = read_manifest(path).frames_done;
            int complete = 0;
            for (const FrameJob& j : d.jobs) complete += outputs_complete(j, opt.layer_output);
            EXPECT_LE(counted, complete) << path << " counts a frame not on disk";
            if (path == opt.manifests[0]) {
                EXPECT_GE(counted, last) << "the manifest went back";
                last = counted;
            }
            ++checks;
        }
    };
    const SequenceResult r = render_sequence(d.asset, d.jobs, opt);
    ASSERT_EQ(r.written, n);
    EXPECT_EQ(checks, 2 * n);
    const auto text = [](const std::string& path) {
        std::ifstream f(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    };
    const SequenceManifest m = read_manifest(opt.manifests[0]);
    EXPECT_EQ(m.frames_done, n);
    EXPECT_EQ(m.frames_total, n);
    EXPECT_EQ(m.exposure, r.exposure);
    EXPECT_EQ(m.exposure_frame, d.jobs[0].rgb);
    EXPECT_EQ(text(opt.manifests[0]), manifest_to_json(m));
    EXPECT_EQ(text(opt.manifests[0]), text(opt.manifests[1]));
    for (const auto& e : fs::directory_iterator(d.dir / "out"))
        EXPECT_NE(e.path().filename().string()[0], '.') << "left behind: " << e.path();
}

TEST(Sequence, ProgressSayingStopEndsAfterTheFramesInFlight) {
    SequenceDir d("stop", 6);
    SequenceOptions opt;
    opt.progress = [](long done, long) { return done < 1; };
    const SequenceResult r = render_sequence(d.asset, d.jobs, opt);
    EXPECT_TRUE(r.interrupted);
    EXPECT_GE(r.written, 1);
    EXPECT_LT(r.written, 6);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(fs::exists(d.jobs[i].output), i < r.written) << i;
    opt.progress = [](long, long) { return false; };  // stopped before it starts
    const SequenceResult none = render_sequence(d.asset, d.jobs, opt);
    EXPECT_TRUE(none.interrupted);
    EXPECT_EQ(none.written, 0);
}

TEST(Sequence, AFrameOfAnotherShapeFailsAloneNamingItsFileWithItsExitCode) {
    SequenceDir d("shape");
    // Frame 1 is square: no scaling of the asset's 4:3 camera gives its view.
    const Camera square{90, 90, 90.0, 90.0, 44.5, 44.5};
    const testing::PlaneScene sq = testing::plane_scene(square);
    write_color(d.jobs[1].rgb, sq.rgb);
    write_depth_exr(d.jobs[1].depth, sq.depth);
    const SequenceResult r = render_sequence(d.asset, d.jobs, SequenceOptions{});
    EXPECT_EQ(r.written, 2);
    ASSERT_EQ(r.errors.size(), 1u);
    ASSERT_EQ(r.error_codes.size(), 1u);
    EXPECT_NE(r.errors[0].find(d.jobs[1].rgb + ": frames are 90x90"), std::string::npos)
        << r.errors[0];
    EXPECT_EQ(r.error_codes[0], AssetError("").exit_code());
    // As the first frame it fits nothing of the sequence: everything stops, naming it.
    try {
        render_sequence(d.asset, {d.jobs[1], d.jobs[0]}, SequenceOptions{});
        FAIL() << "no exception";
    } catch (const AssetError& e) {
        EXPECT_EQ(std::string(e.what()).rfind(d.jobs[1].rgb + ": ", 0), 0u) << e.what();
    }
}

TEST(Sequence, EachFailedFrameKeepsTheExitCodeOfItsError) {
    SequenceDir d("codes");
    fs::remove(d.jobs[0].depth);  // a missing file: an IoError
    const testing::PlaneScene other = testing::plane_scene(Camera{60, 45, 45.0, 45.0, 29.5, 22});
    write_depth_exr(d.jobs[2].depth, other.depth);  // sizes differ: an InputError
    const SequenceResult r = render_sequence(d.asset, d.jobs, SequenceOptions{});
    ASSERT_EQ(r.error_codes.size(), 2u);
    EXPECT_EQ(r.error_codes[0], IoError("").exit_code());
    EXPECT_EQ(r.error_codes[1], InputError("").exit_code());
    EXPECT_NE(r.errors[1].find("sizes differ (120x90 vs 60x45)"), std::string::npos) << r.errors[1];
}

TEST(Sequence, ResumeRendersAgainAFrameCutShort) {
    SequenceDir d("cut", 2);
    render_sequence(d.asset, d.jobs, SequenceOptions{});
    const std::string whole = [&] {
        std::ifstream f(d.jobs[1].output, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(f), {});
    }();
    // The last chunk (IEND, 12 bytes) gone: every row still decodes.
    std::ofstream(d.jobs[1].output, std::ios::binary | std::ios::trunc)
        << whole.substr(0, whole.size() - 12);
    EXPECT_FALSE(image_file_ends(d.jobs[1].output));
    EXPECT_TRUE(image_file_ends(d.jobs[0].output));
    SequenceOptions opt;
    opt.resume = true;
    const SequenceResult r = render_sequence(d.asset, d.jobs, opt);
    EXPECT_EQ(r.skipped, 1);
    EXPECT_EQ(r.written, 1);
    EXPECT_TRUE(image_file_ends(d.jobs[1].output));
}

}  // namespace deepsea
