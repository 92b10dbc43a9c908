// deepsea scene: a procedural RGB-D seafloor flight, written as PNG + depth EXR pairs in the
// layout of a robot simulator's RGB-D output (docs/scene.md).

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/core/error.h"
#include "deepsea/io/config.h"
#include "deepsea/io/image_io.h"
#include "deepsea/scene/flight.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

struct SceneArgs {
    std::string out, camera_file;
    int frames = 8;
    // Intrinsics; 0 means "derive": fx = fy = 0.75 width (the authors' 67 degree view, 600 px
    // at 800), principal point at the image centre.
    int width = 800, height = 800;
    double fx = 0.0, fy = 0.0, cx = -1.0, cy = -1.0;
    FlightParams flight;
    int threads = 0;
};

Camera camera_from(const SceneArgs& a) {
    if (!a.camera_file.empty()) {
        const Setup setup = load_setup({a.camera_file});
        if (!setup.camera) throw ConfigError(a.camera_file + ": no camera section");
        return *setup.camera;
    }
    Camera cam;
    cam.width = a.width;
    cam.height = a.height;
    cam.fx = a.fx > 0.0 ? a.fx : 0.75 * a.width;
    cam.fy = a.fy > 0.0 ? a.fy : cam.fx;
    // width / 2, as the authors' camera (cx = 400 at 800), not the exact centre 399.5.
    cam.cx = a.cx >= 0.0 ? a.cx : 0.5 * a.width;
    cam.cy = a.cy >= 0.0 ? a.cy : 0.5 * a.height;
    return cam;
}

/// The frames' camera as a `camera` section, so that `deepsea render --camera` can use them.
void write_camera_yaml(const fs::path& path, const Camera& cam) {
    Setup setup;
    setup.camera = cam;
    write_setup(path.string(), setup, "# camera of the frames written by deepsea scene\n");
}

void run(SceneArgs a) {
    a.flight.camera = camera_from(a);
    a.flight.frames = a.frames;
    validate_flight(a.flight);  // before anything is written

    const fs::path dir(a.out);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError("cannot create " + dir.string() + ": " + ec.message());

    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point t) {
        return std::chrono::duration<double>(Clock::now() - t).count();
    };
    double render_s = 0.0, write_s = 0.0;
    Progress bar("scene", a.frames);
    for (int i = 0; i < a.frames; ++i) {
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d", i + 1);
        const auto t0 = Clock::now();
        const Frame frame = render_flight_frame(a.flight, i, {a.threads});
        render_s += since(t0);
        const auto t1 = Clock::now();
        write_color((dir / (std::string(name) + ".png")).string(), frame.rgb);
        write_depth_exr((dir / (std::string(name) + "_depth.exr")).string(), frame.depth);
        write_s += since(t1);
        bar.update(i + 1);
    }
    bar.finish();
    write_camera_yaml(dir / "camera.yaml", a.flight.camera);
    const Camera& cam = a.flight.camera;
    std::printf(
        "wrote %d frame%s (%dx%d, altitude %g m, pitch %g deg, seed %llu) to %s: "
        "frame_0001.png + frame_0001_depth.exr ... frame_%04d, camera.yaml\n"
        "per frame: render %.3f s, write %.3f s\n",
        a.frames, a.frames == 1 ? "" : "s", cam.width, cam.height, a.flight.altitude,
        a.flight.pitch_deg, static_cast<unsigned long long>(a.flight.seed), dir.string().c_str(),
        a.frames, render_s / a.frames, write_s / a.frames);
}

}  // namespace

void setup_scene(CLI::App& sub) {
    auto a = std::make_shared<SceneArgs>();
    sub.add_option("--out", a->out, "output directory (created if missing)")->required();
    sub.add_option("--frames", a->frames, "number of frames");
    auto* cam = sub.add_option("--camera", a->camera_file, "YAML file with a camera section");
    sub.add_option("--width", a->width, "image width in pixels")->excludes(cam);
    sub.add_option("--height", a->height, "image height in pixels")->excludes(cam);
    // Defaults that follow from other options: --help shows the rule.
    sub.add_option("--fx", a->fx, "focal length in pixels")
        ->default_str("0.75*width")
        ->excludes(cam);
    sub.add_option("--fy", a->fy, "focal length in pixels")->default_str("fx")->excludes(cam);
    sub.add_option("--cx", a->cx, "principal point in pixels")
        ->default_str("width/2")
        ->excludes(cam);
    sub.add_option("--cy", a->cy, "principal point in pixels")
        ->default_str("height/2")
        ->excludes(cam);
    sub.add_option("--altitude", a->flight.altitude, "metres above the mean seafloor");
    sub.add_option("--speed", a->flight.speed, "metres flown per frame along +x");
    sub.add_option("--pitch", a->flight.pitch_deg, "degrees from straight down, > 0 looks ahead");
    sub.add_option("--seed", a->flight.seed, "seafloor seed: same seed, same frames");
    sub.add_option("--relief", a->flight.relief, "height scale of the relief, 0 = flat");
    sub.add_option("--max-range", a->flight.max_range,
                   "metres along a ray beyond which depth is 0");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
