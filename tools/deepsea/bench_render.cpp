// deepsea bench's renderer cases (bench.h): the compositor on generated frames (with and
// without lamp shadows, through a flat port), marine snow alone, lamp shadows alone.

#include <malloc.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <optional>
#include <utility>

#include "bench.h"
#include "cli_util.h"
#include "commands.h"
#include "deepsea/bake/bake.h"
#include "deepsea/batch/sequence.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/jerlov.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/lamp_shadows.h"
#include "deepsea/runtime/renderer.h"
#include "deepsea/scene/flight.h"

namespace deepsea::cli::bench {

namespace {

/// The compositor's cases: each layer set (all layers, then only the image), without and with
/// lamp shadows.
const char* const kCompositeCases[] = {"composite", "composite_final_only", "composite-shadows",
                                       "composite_final_only-shadows"};

/// The close survey (docs/snow-shadows.md, "Cost"): 1 m above a floor of 2.5 times the usual
/// relief, the camera pitched 40 degrees forward, where the demo's lamps cast shadows (the
/// default flight's first frame, 3 m above the floor looking straight down, has none).
FlightParams survey_flight(const Camera& cam) {
    FlightParams fp;
    fp.camera = cam;
    fp.pitch_deg = 40.0;
    fp.altitude = 1.0;
    fp.relief = 2.5;
    return fp;
}

}  // namespace

/// Composites one generated frame repeatedly, for each layer set (all layers, then only the
/// image), without and with lamp shadows, then all layers through a flat port (an asset baked
/// through it, and the pinhole asset): one frame per camera, a fresh compositor and peak window
/// per case.
std::vector<Case> time_compositor(const Asset& asset, const Camera& cam, const BenchArgs& a,
                                  int threads) {
    FlightParams flight;
    flight.camera = cam;
    Frame frame = render_flight_frame(flight, 0);
    std::vector<Case> cases;
    const auto time = [&](const std::string& name, const RenderSettings& settings, LayerSet set,
                          const Asset* other = nullptr) {
        Renderer renderer(other ? *other : asset, settings);
        // From here on only what the runtime holds: the asset, one frame, the compositor (made
        // by the first frame, which also allocates).
        reset_peak_rss();
        Layers layers;
        renderer.render(layers, frame, set);
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            renderer.render(layers, frame, set);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    };
    for (int k = 0; k < 4; ++k) {
        if (!wanted(a.cases, kCompositeCases[k])) continue;
        RenderSettings settings;
        settings.camera = cam;
        settings.shadows = k >= 2;
        time(kCompositeCases[k], settings, k % 2 == 0 ? LayerSet::All : LayerSet::Final);
    }
    // Two renderers' all layers frame by frame in turn: paired timings, so that the machine's
    // drift does not fall on one of the two.
    const auto paired = [&](const std::string& name0, Renderer& r0, const std::string& name1,
                            Renderer& r1) {
        Layers l0, l1;
        r0.render(l0, frame, LayerSet::All);
        r1.render(l1, frame, LayerSet::All);
        std::vector<double> t[2], cpu[2];
        for (int r = 0; r < a.repeats; ++r) {
            for (int k = 0; k < 2; ++k) {
                const double t0 = now_ms(), c0 = cpu_ms();
                (k == 0 ? r0 : r1).render(k == 0 ? l0 : l1, frame, LayerSet::All);
                t[k].push_back(now_ms() - t0);
                cpu[k].push_back(cpu_ms() - c0);
            }
        }
        cases.push_back(summarize(name0, cam.width, cam.height, threads, t[0], cpu[0]));
        cases.push_back(summarize(name1, cam.width, cam.height, threads, t[1], cpu[1]));
    };
    if (asset.forward_psf && wanted(a.cases, "composite_small_angle")) {
        // All layers with the asset's forward scatter from transport and, in turn, with the
        // small-angle point spread that assets without the table get.
        Asset small_angle = asset;
        small_angle.forward_psf.reset();
        RenderSettings plain;
        plain.camera = cam;
        Renderer table(asset, plain), small(small_angle, plain);
        paired("composite_transport_psf", table, "composite_small_angle", small);
    }
    RenderSettings port_settings;
    port_settings.camera = cam;
    port_settings.port = Port{};
    port_settings.port->flat.distance = 0.03;
    port_settings.port->flat.glass_thickness = 0.012;
    if (wanted(a.cases, "composite_flat_port")) {
        // Through a flat port (3 cm from the camera centre, 1.2 cm of acrylic, seawater): every
        // pixel's water-side ray marched through the frame's depth (docs/ports.md), the asset
        // baked through the port (its columns the water-side rays, looked up as a pinhole
        // frame's).
        BakeSettings through = bench_bake(a);
        through.port = port_settings.port;
        const Asset port_asset = bake(cam, asset.info.rig, asset.info.water, through);
        // in turn with the same frame without a port (composite_flat_port_base), whose ratio
        // is the port's cost (docs/ports.md, "Speed")
        RenderSettings plain;
        plain.camera = cam;
        Renderer port(port_asset, port_settings), pinhole(asset, plain);
        paired("composite_flat_port", port, "composite_flat_port_base", pinhole);
    }
    // The same with the pinhole asset, looked up through the port (port_backscatter.h).
    if (wanted(a.cases, "composite_flat_port_pinhole"))
        time("composite_flat_port_pinhole", port_settings, LayerSet::All);
    return cases;
}

/// Marine snow alone (MarineSnow::draw: placing, lighting and drawing the particles into the
/// image) at each preset's density, on the flight's first frame, the camera moving along the
/// flight from one run to the next (particles fixed in the world); `snow-streaks` the nepheloid
/// preset drawn as motion streaks, the camera moving at 1 m/s (the flight's 0.25 m a frame
/// taken 0.25 s apart) with a 10 ms exposure: 1 cm in it; then `snow-shadows`: the nepheloid
/// preset's snow and the lamps' shadows (LampShadows::compute, the default step) together, and
/// `snow-shadows-survey`: the same on the close survey's first frame (survey_flight()), where
/// the lamps cast shadows.
std::vector<Case> time_snow(const Asset& asset, const Camera& cam, const BenchArgs& a,
                            int threads) {
    std::vector<Case> cases;
    FlightParams flight;
    flight.camera = cam;
    const Frame frame = render_flight_frame(flight, 0);
    std::vector<std::pair<std::string, std::string>> runs;  // case, preset
    for (const std::string& preset : snow_preset_names())
        runs.emplace_back("snow-" + preset, preset);
    runs.emplace_back("snow-streaks", "nepheloid");
    for (const auto& [name, preset] : runs) {
        if (!wanted(a.cases, name)) continue;
        SnowSettings s;
        s.snow = snow_preset(preset);
        s.streaks = name == "snow-streaks";
        MarineSnow snow(s, asset.info.rig, asset.info.water);
        Image final(cam.width, cam.height, 3);
        std::vector<double> t, cpu;
        long particles = 0;
        const auto pose = [&](int r) {
            const FlightPose p = flight_pose(flight, r);
            return CameraPose{p.origin, p.right, p.down, p.forward};
        };
        for (int r = 0; r <= a.repeats; ++r) {
            const double dt = flight.speed / 1.0;  // seconds a frame at 1 m/s
            snow.set_frame(std::uint64_t(r), pose(r),
                           shutter_poses(pose(r), r * dt, pose(r + 1), (r + 1) * dt, 0.010));
            const double t0 = now_ms(), c0 = cpu_ms();
            snow.draw(cam, frame.depth, final, nullptr, nullptr);
            if (r == 0) continue;  // the first run allocates
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
            particles += snow.drawn();
        }
        detail("%s: %ld particles drawn per frame on average\n", name.c_str(),
               particles / std::max(a.repeats, 1));
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    }
    // The budget as stated: the lamps' shadows (the default step) and the densest
    // preset's snow on one frame, as `deepsea demo --snow nepheloid` renders them; on the
    // flight's first frame (no shadowed pixel with the demo's lamps: the sweep and the lit
    // rows alone) and on the close survey's (shadows cast).
    for (const bool survey : {false, true}) {
        const std::string name = survey ? "snow-shadows-survey" : "snow-shadows";
        if (!wanted(a.cases, name)) continue;
        const FlightParams fp = survey ? survey_flight(cam) : flight;
        const Frame f = survey ? render_flight_frame(fp, 0) : frame;
        SnowSettings s;
        s.snow = snow_preset("nepheloid");
        MarineSnow snow(s, asset.info.rig, asset.info.water);
        LampShadows shadows;
        Image final(cam.width, cam.height, 3);
        std::vector<double> t, cpu;
        for (int r = 0; r <= a.repeats; ++r) {
            const FlightPose p = flight_pose(fp, r);
            snow.set_frame(std::uint64_t(r), CameraPose{p.origin, p.right, p.down, p.forward});
            const double t0 = now_ms(), c0 = cpu_ms();
            shadows.compute(cam, f.depth, asset.info.rig, ShadowSettings{true});
            snow.draw(cam, f.depth, final, nullptr, nullptr);
            if (r == 0) continue;  // the first run allocates
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    }
    return cases;
}

/// Lamp shadows alone (LampShadows::compute: every lamp's visibility image) with the setup's
/// rig: on the flight's first frame, `shadows` as rendered, `shadows-exact` the full-resolution
/// sweep it is checked against (docs/snow-shadows.md, "Lamp shadows"); `shadows-survey` as
/// rendered on the close survey's first frame (survey_flight()), where the lamps cast shadows.
std::vector<Case> time_shadows(const Camera& cam, const Rig& rig, const BenchArgs& a, int threads) {
    std::vector<Case> cases;
    FlightParams flight;
    flight.camera = cam;
    const Frame frame = render_flight_frame(flight, 0);
    for (const char* name : {"shadows", "shadows-exact", "shadows-survey"}) {
        if (!wanted(a.cases, name)) continue;
        const bool survey = std::string(name) == "shadows-survey";
        ShadowSettings s{true};
        if (std::string(name) == "shadows-exact") s.step = 1;
        const Frame f = survey ? render_flight_frame(survey_flight(cam), 0) : Frame{};
        const Image& depth = survey ? f.depth : frame.depth;
        LampShadows shadows;
        shadows.compute(cam, depth, rig, s);  // the first run allocates
        std::vector<double> t, cpu;
        for (int r = 0; r < a.repeats; ++r) {
            const double t0 = now_ms(), c0 = cpu_ms();
            shadows.compute(cam, depth, rig, s);
            t.push_back(now_ms() - t0);
            cpu.push_back(cpu_ms() - c0);
        }
        cases.push_back(summarize(name, cam.width, cam.height, threads, t, cpu));
    }
    return cases;
}

}  // namespace deepsea::cli::bench
