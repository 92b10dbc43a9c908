// deepsea demo: the main job on the embedded default. A procedural seafloor flight, the
// default asset (baked if missing or stale), the rendered sequence (radiance with one exposure
// factor), the same frames recorded by the setup's camera stage, and a contact sheet.

#include <cstdio>
#include <filesystem>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/bake.h"
#include "deepsea/batch/contact_sheet.h"
#include "deepsea/batch/sequence.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/image_io.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/scene/flight.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

struct DemoArgs {
    std::string out = "out/demo";
    std::string config = default_demo_config();
    int frames = 8;
    std::uint64_t seed = 1;
    std::string scattering = "multiple";
    std::string snow = "abyssal";
    int threads = 0;
};

/// The asset for the demo setup: reuse `path` if its inputs are unchanged, else bake it.
Asset demo_asset(const Setup& setup, const std::string& path, Scattering scattering, int threads) {
    BakeSettings settings;
    settings.scattering = scattering;
    settings.port = setup.port;  // baked along its water-side rays (docs/ports.md)
    // Unreadable, stale or of an older format: bake a new one below.
    if (asset_up_to_date(
            path, bake_request(*setup.camera, *setup.rig, *setup.water, settings).input_hash)) {
        say("asset: %s (up to date)\n", path.c_str());
        return load_asset(path);
    }
    Progress bar("bake", 1);
    Asset a = bake(*setup.camera, *setup.rig, *setup.water, settings,
                   {threads, 0, [&](long done, long total) {
                        bar.set_total(total);
                        bar.update(done);
                        return true;
                    }});
    bar.finish();
    write_asset(path, a);
    say("asset: baked %s\n", path.c_str());
    return a;
}

void run(const DemoArgs& a) {
    if (a.frames < 1) throw ConfigError("--frames must be >= 1");
    Setup setup = load_setup({a.config});
    require_complete(setup, a.config);
    const fs::path out(a.out), input = out / "input", frames = out / "frames",
                               layers = out / "layers", recorded = out / "camera";
    for (const fs::path& d : {input, frames, layers, recorded}) {
        std::error_code ec;
        fs::create_directories(d, ec);
        if (ec) throw IoError("cannot create " + d.string() + ": " + ec.message());
    }

    // 1. the in-air RGB-D flight
    FlightParams flight;
    flight.camera = *setup.camera;
    flight.frames = a.frames;
    flight.seed = a.seed;
    std::vector<FrameJob> jobs;
    Progress scene_bar("scene", a.frames);
    for (int i = 0; i < a.frames; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d", i + 1);
        const Frame f = render_flight_frame(flight, i, {a.threads});
        FrameJob j;
        j.rgb = (input / (std::string(name) + ".png")).string();
        j.depth = (input / (std::string(name) + "_depth.exr")).string();
        j.output = (frames / (std::string(name) + ".png")).string();
        j.layers = (layers / (std::string(name) + ".exr")).string();
        const FlightPose pose = flight_pose(flight, i);  // the snow stays in the world
        j.pose = CameraPose{pose.origin, pose.right, pose.down, pose.forward};
        write_color(j.rgb, f.rgb);
        write_depth_exr(j.depth, f.depth);
        jobs.push_back(j);
        scene_bar.update(i + 1);
    }
    scene_bar.finish();
    say("scene: %d frames in %s\n", a.frames, input.c_str());

    // 2. the asset, 3. the sequence
    const Asset asset =
        demo_asset(setup, (out / "demo.vdb").string(), parse_scattering(a.scattering), a.threads);
    SequenceOptions opt;
    // the lamps' shadows: what marks a deep-sea photograph (not built through a port)
    opt.shadows = !setup.port;
    opt.port = setup.port;  // rendered through it, as baked
    // and the lit particles (not built through a port either)
    if (!setup.port) opt.snow = snow_settings(a.snow, a.seed, setup.camera_model);
    Progress bar("render", a.frames);
    opt.on_frame = frame_lines();
    opt.progress = [&](long done, long) {
        bar.update(done);
        return true;
    };
    SequenceResult r;
    in_arena(a.threads, [&] { r = render_sequence(asset, jobs, opt); });
    bar.finish();
    for (const auto& e : r.errors) std::fprintf(stderr, "deepsea: error: %s\n", e.c_str());
    say("render: %d frames in %.2f s -> %s\n", r.written, r.seconds, frames.c_str());

    // 4. the same frames recorded by the setup's camera (lens, sensor, processing, auto
    // exposure: docs/camera.md)
    std::vector<FrameJob> camera_jobs;
    if (setup.camera_model) {
        for (FrameJob j : jobs) {
            j.output = (recorded / fs::path(j.output).filename()).string();
            j.layers.clear();
            camera_jobs.push_back(j);
        }
        SequenceOptions cam;
        cam.shadows = !setup.port;
        cam.port = setup.port;
        cam.snow = opt.snow;
        cam.camera_model = setup.camera_model;
        cam.layer_output.camera = true;
        Progress cam_bar("camera", a.frames);
        cam.progress = [&](long done, long) {
            cam_bar.update(done);
            return true;
        };
        SequenceResult c;
        in_arena(a.threads, [&] { c = render_sequence(asset, camera_jobs, cam); });
        cam_bar.finish();
        for (const auto& e : c.errors) std::fprintf(stderr, "deepsea: error: %s\n", e.c_str());
        say("camera: %d frames in %.2f s -> %s (last frame %.3g ms, %.3g DN/e-)\n", c.written,
            c.seconds, recorded.c_str(), c.camera_exposure.exposure_time_ms,
            c.camera_exposure.system_gain);
        r.errors.insert(r.errors.end(), c.errors.begin(), c.errors.end());
    }

    // 5. contact sheet: in-air | depth | direct | backscatter | final | camera, up to 4 frames
    std::vector<std::vector<Image>> rows;
    const int shown = std::min(a.frames, 4);
    for (int s = 0; s < shown; ++s) {
        const std::size_t k = std::size_t(s) * (a.frames - 1) / std::max(shown - 1, 1);
        const FrameJob& j = jobs[k];
        const std::vector<std::string> rgb{"R", "G", "B"};
        rows.push_back({read_color(j.rgb), depth_picture(read_depth(j.depth)),
                        apply_exposure(read_exr_layer(j.layers, "direct", rgb), r.exposure),
                        apply_exposure(read_exr_layer(j.layers, "backscatter", rgb), r.exposure),
                        read_color(j.output)});
        if (!camera_jobs.empty()) rows.back().push_back(read_color(camera_jobs[k].output));
    }
    const std::string sheet = (out / "contact_sheet.png").string();
    write_color(sheet, contact_sheet(rows, 256));
    say("contact sheet (in-air | depth | direct | backscatter | final%s): %s\n",
        camera_jobs.empty() ? "" : " | camera", sheet.c_str());
    say("demo output in %s\n", fs::absolute(out).c_str());
    if (!r.errors.empty()) throw FramesFailed("some frames failed (listed above)");
}

}  // namespace

void setup_demo(CLI::App& sub) {
    auto a = std::make_shared<DemoArgs>();
    sub.add_option("--out", a->out, "output folder");
    sub.add_option("--config", a->config, "setup YAML (camera, rig, water)");
    sub.add_option("--frames", a->frames, "frames to generate and render");
    sub.add_option("--seed", a->seed, "seafloor seed");
    sub.add_option("--scattering", a->scattering,
                   "the asset's water light: multiple (all orders) or single (the paper's model)");
    sub.add_option("--snow", a->snow,
                   "marine snow: abyssal (the default), nepheloid, plume or off");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
