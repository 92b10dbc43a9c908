#include "deepsea/batch/sequence_manifest.h"

#include <gtest/gtest.h>

#include <fstream>

#include "../temp_folder.h"
#include "deepsea/core/error.h"
#include "deepsea/runtime/lamp_shadows.h"

namespace deepsea {

namespace fs = std::filesystem;

namespace {

class ManifestTest : public test::TempFolderTest {};

SequenceManifest example() {
    SequenceManifest m;
    m.deepsea_version = "0.1.0";
    m.asset_hash = "fnv1a64:0123456789abcdef";
    m.rgb = "/data/in/*.png";
    m.depth = "/data/in/*_depth.exr";
    m.camera = {320, 240, 240.0, 240.0, 159.5, 119.5};
    m.percentile = 0.995;
    m.target = 0.85;
    m.max_clipped = 0.005;
    m.exposure = 160.08450200258105;
    m.exposure_frame = "/data/in/frame_0001.png";
    m.image = true;
    m.layers = true;
    m.frames_total = 10;
    m.frames_done = 4;
    return m;
}

/// The message of the ConfigError check_resumable throws, empty if none.
std::string refusal(const SequenceManifest& folder, const SequenceManifest& run) {
    try {
        check_resumable(folder, run, "out/deepsea-sequence.json");
    } catch (const ConfigError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_F(ManifestTest, RoundTripsExactlyThroughTheFile) {
    const SequenceManifest m = example();
    write_manifest(path("m.json"), m);
    const SequenceManifest r = read_manifest(path("m.json"));
    EXPECT_EQ(r.exposure, m.exposure);  // bit for bit: a resumed frame must match
    EXPECT_EQ(r.camera, m.camera);
    EXPECT_EQ(r.asset_hash, m.asset_hash);
    EXPECT_EQ(r.exposure_frame, m.exposure_frame);
    EXPECT_EQ(r.frames_done, 4);
    EXPECT_EQ(r.frames_total, 10);
    EXPECT_TRUE(r.image && r.layers && r.auto_exposure && r.forward);
    EXPECT_EQ(manifest_to_json(r), manifest_to_json(m));
    SequenceManifest some = m;
    some.layer_set = "final,depth";
    some.half = true;
    const SequenceManifest r2 = manifest_from_json(manifest_to_json(some), "m2.json");
    EXPECT_EQ(r2.layer_set, "final,depth");
    EXPECT_TRUE(r2.half);
    some.image_format = "jpg";
    EXPECT_EQ(manifest_from_json(manifest_to_json(some), "m3.json").image_format, "jpg");
    // shadows: written only when on; a manifest without the key (older ones) reads as off
    EXPECT_EQ(manifest_to_json(m).find("shadows"), std::string::npos);
    EXPECT_FALSE(r.shadows);
    some.shadows = true;
    EXPECT_TRUE(manifest_from_json(manifest_to_json(some), "m5.json").shadows);
    // the step with them (absent, as in manifests from before --shadow-step: the default)
    some.shadow_step = 3;
    EXPECT_EQ(manifest_from_json(manifest_to_json(some), "m6.json").shadow_step, 3);
    std::string no_step = manifest_to_json(some);
    const std::size_t at = no_step.find("\"shadow_step\"");
    ASSERT_NE(at, std::string::npos);
    no_step.erase(at, no_step.find(',', at) + 1 - at);  // ("shadows" follows it)
    EXPECT_EQ(manifest_from_json(no_step, "m7.json").shadow_step, kDefaultShadowStep);
    some.shadows = false;
    some.image = false;  // no -o: "none", and the format stays png
    EXPECT_EQ(manifest_from_json(manifest_to_json(some), "m4.json").image_format, "png");
    EXPECT_EQ(listing().size(), 1u);  // no temporary left beside it
}

TEST_F(ManifestTest, DamagedManifestsNameTheFileAndKey) {
    const auto message = [&](const std::string& text) {
        std::ofstream(path("m.json")) << text;
        try {
            read_manifest(path("m.json"));
        } catch (const InputError& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(message("{not json").find("m.json: not a deepsea sequence manifest"),
              std::string::npos);
    std::string text = manifest_to_json(example());
    EXPECT_NE(
        message(text.replace(text.find("\"format\": 1"), 11, "\"format\": 9")).find("format 9"),
        std::string::npos);
    text = manifest_to_json(example());
    EXPECT_NE(message(text.replace(text.find("\"asset_hash\""), 12, "\"asset_hush\""))
                  .find("m.json: asset_hash: missing"),
              std::string::npos);
    text = manifest_to_json(example());
    const std::size_t at = text.find("\"width\": 320");
    EXPECT_NE(message(text.replace(at, 12, "\"width\": \"x\"")).find("camera.width: wrong type"),
              std::string::npos);
    EXPECT_THROW(read_manifest(path("absent.json")), IoError);
}

TEST(Manifest, ResumeRefusesEverySettingThatChangesTheFrames) {
    const SequenceManifest folder = example();
    SequenceManifest run = folder;
    run.exposure = 0;  // an auto run has not chosen yet: the folder's factor is kept
    run.frames_done = 0;
    EXPECT_EQ(refusal(folder, run), "");
    const auto changed = [&](auto edit) {
        SequenceManifest r = run;
        edit(r);
        return refusal(folder, r);
    };
    EXPECT_NE(changed([](auto& r) { r.asset_hash = "fnv1a64:ffff"; }).find("the asset was"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.deepsea_version = "0.2.0"; }).find("version"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.camera.fx = 250; }).find("camera"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.auto_exposure = false; }).find("exposure"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.target = 0.5; }).find("auto exposure"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.layers = false; }).find("--layers"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.bits = 16; }).find("--bits"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.image_format = "jpg"; }).find("--format was png, now jpg"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.layer_set = "final,depth"; }).find("--layer-set"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.half = true; }).find("--half"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.forward = false; }).find("forward"), std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.shadows = true; }).find("--shadows was off, now on"),
              std::string::npos);
    {
        SequenceManifest shadowed = folder, other = run;
        shadowed.shadows = other.shadows = true;
        other.shadow_step = 4;
        EXPECT_NE(refusal(shadowed, other).find("--shadow-step was 2, now 4"), std::string::npos);
    }
    EXPECT_NE(changed([](auto& r) { r.depth_scale = 0.0001; }).find("--depth-scale"),
              std::string::npos);
    EXPECT_NE(changed([](auto& r) { r.rgb = "/other/*.png"; }).find("holds the frames of"),
              std::string::npos);
    SequenceManifest fixed = folder;
    fixed.auto_exposure = false;
    SequenceManifest fixed_run = fixed;
    fixed_run.exposure = 2.0;
    EXPECT_NE(refusal(fixed, fixed_run).find("the exposure was"), std::string::npos);
    // Only the frame count and which frame chose the exposure may differ.
    run.frames_total = 12;
    EXPECT_EQ(refusal(folder, run), "");
}

TEST(Manifest, PosesAreRecordedAndResumeWithOtherPosesIsRefused) {
    std::vector<FrameJob> jobs(3);
    EXPECT_EQ(poses_hash(jobs), "");  // no poses: no key, as before poses were recorded
    for (std::size_t i = 0; i < jobs.size(); ++i) {
        CameraPose p;
        p.origin = {0.1 * double(i), 0.0, -2.0};
        jobs[i].pose = p;
    }
    SequenceManifest folder = example();
    folder.poses_hash = poses_hash(jobs);
    folder.poses = 3;
    EXPECT_EQ(folder.poses_hash.rfind("fnv1a64:", 0), 0u);
    const SequenceManifest back = manifest_from_json(manifest_to_json(folder), "m.json");
    EXPECT_EQ(back.poses_hash, folder.poses_hash);
    EXPECT_EQ(back.poses, 3);
    EXPECT_EQ(manifest_from_json(manifest_to_json(example()), "m.json").poses_hash, "");

    // the same poses resume; one pose moved by a millimetre, two swapped, or none: refused in
    // one line naming --poses
    SequenceManifest run = folder;
    EXPECT_EQ(refusal(folder, run), "");
    for (int edit = 0; edit < 3; ++edit) {
        std::vector<FrameJob> other = jobs;
        if (edit == 0) other[1].pose->origin.x += 1e-3;
        if (edit == 1) std::swap(other[0], other[2]);
        if (edit == 2)
            for (FrameJob& j : other) j.pose.reset();
        run.poses_hash = poses_hash(other);
        const std::string msg = refusal(folder, run);
        EXPECT_NE(msg.find("--poses was 3 pose(s)"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos);
    }
}

TEST(Manifest, AShardRecordRoundTripsAndIsPartOfWhatResumeKeeps) {
    SequenceManifest m = example();
    EXPECT_EQ(manifest_to_json(m).find("shard"), std::string::npos);  // unsharded: as before
    m.shard = ShardRecord{3, 4, 10, "/data/out", ""};
    const SequenceManifest r = manifest_from_json(manifest_to_json(m), "s.json");
    ASSERT_TRUE(r.shard);
    EXPECT_EQ(r.shard->index, 3);
    EXPECT_EQ(r.shard->count, 4);
    EXPECT_EQ(r.shard->sequence_frames, 10);
    EXPECT_EQ(r.shard->image_folder, "/data/out");
    EXPECT_EQ(manifest_to_json(r), manifest_to_json(m));
    EXPECT_EQ(shard_manifest_name(3, 4), "deepsea-sequence.shard-0003-of-0004.json");
    EXPECT_EQ(shard_manifest_name(3, 12000), "deepsea-sequence.shard-0003-of-12000.json");
    SequenceManifest other = m;
    other.shard->sequence_frames = 11;  // the inputs changed: the shard's frames moved
    EXPECT_NE(refusal(m, other).find("the part rendered was shard 3/4 of 10 frames"),
              std::string::npos);
    std::string text = manifest_to_json(m);
    text.replace(text.find("\"index\": 3"), 10, "\"index\": 4");
    EXPECT_THROW(manifest_from_json(text, "s.json"), InputError);
}

TEST(Manifest, FirstDifferenceNamesTheKeyAndBothValues) {
    SequenceManifest a = example(), b = example();
    EXPECT_EQ(first_difference(a, b, {}), "");
    b.exposure = 2.0;
    EXPECT_EQ(first_difference(a, b, {}).rfind("exposure.factor: 160.08", 0), 0u);
    b = a;
    b.frames_done = 9;
    b.shard = ShardRecord{1, 2, 20, "/o", ""};
    EXPECT_NE(first_difference(a, b, {}), "");
    EXPECT_EQ(first_difference(a, b, {"frames", "shard"}), "");
}

}  // namespace deepsea
