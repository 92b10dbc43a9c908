// deepsea scene: a procedural RGB-D seafloor flight, written as PNG + depth EXR pairs in the
// layout of a robot simulator's RGB-D output (docs/scene.md).

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/io/config.h"
#include "deepsea/io/image_io.h"
#include "deepsea/scene/flight.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

constexpr double kDerive = std::numeric_limits<double>::quiet_NaN();

struct SceneArgs {
    std::string out, camera_file;
    int frames = 8;
    // Intrinsics; NaN (which no flag accepts) means "derive": fx = fy = 0.75 width (the
    // authors' 67 degree view, 600 px at 800), principal point at the image centre.
    int width = 800, height = 800;
    double fx = kDerive, fy = kDerive, cx = kDerive, cy = kDerive;
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
    cam.fx = std::isnan(a.fx) ? 0.75 * a.width : a.fx;
    cam.fy = std::isnan(a.fy) ? cam.fx : a.fy;
    // width / 2, as the authors' camera (cx = 400 at 800), not the exact centre 399.5.
    cam.cx = std::isnan(a.cx) ? 0.5 * a.width : a.cx;
    cam.cy = std::isnan(a.cy) ? 0.5 * a.height : a.cy;
    return cam;
}

/// A frame file of a scene: frame_NNNN.png or frame_NNNN_depth.exr; its number, or 0.
int scene_frame_number(const std::string& name) {
    int n = 0, used = 0;
    if (std::sscanf(name.c_str(), "frame_%d%n", &n, &used) != 1 || n < 1) return 0;
    const std::string tail = name.substr(std::size_t(used));
    return tail == ".png" || tail == "_depth.exr" ? n : 0;
}

/// --out may be new, empty, or a folder of an earlier scene that this one overwrites whole:
/// frames of another camera, or numbered beyond this flight's, would be left beside the new
/// ones, and a render of the folder would mix two flights (or fail on their sizes).
void check_out_folder(const fs::path& dir, const FlightParams& flight) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) return;
    if (!fs::is_directory(dir, ec)) throw IoError(dir.string() + ": --out is a file, not a folder");
    int beyond = 0, frames = 0;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const int n = scene_frame_number(entry.path().filename().string());
        if (n > 0) ++frames;
        if (n > flight.frames) ++beyond;
    }
    if (frames == 0) return;
    std::string other;
    const fs::path yaml = dir / "camera.yaml";
    if (beyond > 0) {
        other = std::to_string(beyond) + " frame file(s) numbered beyond this flight's " +
                std::to_string(flight.frames);
    } else if (!fs::exists(yaml, ec)) {
        other = "frame files without the camera.yaml of a scene";
    } else {
        const Setup earlier = load_setup({yaml.string()});
        const Camera& c = flight.camera;
        if (!earlier.camera || earlier.camera->width != c.width ||
            earlier.camera->height != c.height || earlier.camera->fx != c.fx ||
            earlier.camera->fy != c.fy || earlier.camera->cx != c.cx || earlier.camera->cy != c.cy)
            other = "the frames of another camera (" + yaml.string() + ")";
    }
    if (!other.empty()) {
        throw IoError(dir.string() + ": --out holds " + other +
                      ", which this scene would leave beside its own; write into an empty or "
                      "new folder");
    }
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
    check_out_folder(dir, a.flight);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw IoError("cannot create " + dir.string() + ": " + ec.message());
    const StopOnSignals stop;

    using Clock = std::chrono::steady_clock;
    auto since = [](Clock::time_point t) {
        return std::chrono::duration<double>(Clock::now() - t).count();
    };
    double render_s = 0.0, write_s = 0.0;
    Progress bar("scene", a.frames);
    // First: a stopped scene's folder is one that the same command may write into again.
    write_camera_yaml(dir / "camera.yaml", a.flight.camera);
    const auto stopped = [&](int done) {
        return Cancelled("stopped by signal " + std::to_string(stop_signal()) + " after " +
                         std::to_string(done) + " of " + std::to_string(a.frames) +
                         " frame(s); every file written is complete");
    };
    // Asked within a few rows, not only between frames (a large frame takes seconds).
    const Parallel par{a.threads, 0, [](long, long) { return stop_signal() == 0; }};
    for (int i = 0; i < a.frames; ++i) {
        if (stop_signal() != 0) throw stopped(i);
        char name[32];
        std::snprintf(name, sizeof name, "frame_%04d", i + 1);
        const auto t0 = Clock::now();
        Frame frame;
        try {
            frame = render_flight_frame(a.flight, i, par);
        } catch (const Cancelled&) {
            throw stopped(i);
        }
        render_s += since(t0);
        const auto t1 = Clock::now();
        write_color((dir / (std::string(name) + ".png")).string(), frame.rgb);
        write_depth_exr((dir / (std::string(name) + "_depth.exr")).string(), frame.depth);
        write_s += since(t1);
        detail("wrote %s.png, %s_depth.exr\n", (dir / name).c_str(), name);
        bar.update(i + 1);
    }
    bar.finish();
    const Camera& cam = a.flight.camera;
    say("wrote %d frame%s (%dx%d, altitude %g m, pitch %g deg, seed %llu) to %s: "
        "frame_0001.png + frame_0001_depth.exr ... frame_%04d, camera.yaml\n"
        "per frame: render %.3f s, write %.3f s\n",
        a.frames, a.frames == 1 ? "" : "s", cam.width, cam.height, a.flight.altitude,
        a.flight.pitch_deg, static_cast<unsigned long long>(a.flight.seed), dir.string().c_str(),
        a.frames, render_s / a.frames, write_s / a.frames);
}

/// A number that is finite (and > 0): CLI11's PositiveNumber lets NaN through.
CLI::Validator finite(bool positive = false) {
    return CLI::Validator(
        [positive](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || *end != '\0' || !std::isfinite(v) || (positive && !(v > 0.0)))
                return std::string("must be a finite number") + (positive ? " > 0" : "") +
                       ", got '" + text + "'";
            return "";
        },
        "");
}

}  // namespace

void setup_scene(CLI::App& sub) {
    auto a = std::make_shared<SceneArgs>();
    sub.add_option("--out", a->out, "output directory (created if missing)")->required();
    sub.add_option("--frames", a->frames, "number of frames")
        ->check(CLI::Range(1, kMaxFlightFrames));
    auto* cam = sub.add_option("--camera", a->camera_file, "YAML file with a camera section");
    sub.add_option("--width", a->width, "image width in pixels")
        ->check(CLI::Range(1, kMaxFlightSide))
        ->excludes(cam);
    sub.add_option("--height", a->height, "image height in pixels")
        ->check(CLI::Range(1, kMaxFlightSide))
        ->excludes(cam);
    // Defaults that follow from other options: --help shows the rule.
    const auto intrinsic = [&](const char* flag, double& value, const char* what, const char* rule,
                               bool positive) {
        sub.add_option(flag, value, what)
            ->default_str(rule)
            ->check(finite(positive))
            ->excludes(cam);
    };
    intrinsic("--fx", a->fx, "focal length in pixels", "0.75*width", true);
    intrinsic("--fy", a->fy, "focal length in pixels", "fx", true);
    intrinsic("--cx", a->cx, "principal point in pixels", "width/2", false);
    intrinsic("--cy", a->cy, "principal point in pixels", "height/2", false);
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
