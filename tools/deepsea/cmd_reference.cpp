// deepsea reference: exact per-pixel rendering (no asset), the ground truth: single scattering
// by quadrature, or all orders by the path tracer (--scattering multiple).

#include <chrono>
#include <cstdio>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
#include "deepsea/optics/port_hit.h"
#include "deepsea/reference/path_tracer.h"
#include "deepsea/reference/reference.h"
#include "deepsea/runtime/exposure.h"

namespace deepsea::cli {

namespace {

struct ReferenceArgs {
    SetupFlags setup;
    DepthFlags depth;
    std::string rgb, depth_path, layers, output, exposure = "auto";
    double z_max = 0.0;
    double rel_tol = 1e-7;
    int threads = 0;
    std::string scattering = "single";
    PathTracerOptions paths;  ///< --scattering multiple
};

/// Exposes and writes the final layer to -o.
void write_exposed(const std::string& path, const Exposure& exposure, const Image& final) {
    const double f = exposure_factor(exposure, final);
    write_color(path, apply_exposure(final, f));
    say("wrote %s (exposure %.6g)\n", path.c_str(), f);
}

/// --scattering multiple: the path tracer, with its standard errors as layers final_se,
/// direct_se, forward_se and backscatter_se beside the estimates.
void run_multiple(const ReferenceArgs& a, const Setup& setup, const Image& rgb, const Image& depth,
                  const Exposure& exposure) {
    PathTracerOptions opt = a.paths;
    opt.open_water_z = a.z_max;
    Progress bar("reference", 1);
    const StopOnSignals stop;
    const auto t0 = std::chrono::steady_clock::now();
    Parallel par(a.threads, 0, [&](long done, long total) {
        bar.set_total(total);
        bar.update(done);
        return stop_signal() == 0;
    });
    const PathTraced pt = [&] {
        try {
            return render_path_traced(*setup.camera, *setup.rig, *setup.water, rgb, depth, opt,
                                      par.with_stop(&stop_flag()));
        } catch (const Cancelled&) {
            throw Cancelled("stopped by signal " + std::to_string(stop_signal()) +
                            "; nothing was written");
        }
    }();
    bar.finish();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double paths = double(a.paths.paths) * rgb.width * rgb.height;
    say("traced %.4g paths in %.1f s (%.3g paths/s)\n", paths, s, paths / s);
    for (int ch = 0; ch < 3; ++ch) {
        double sum = 0.0, var = 0.0;
        for (int v = 0; v < rgb.height; ++v) {
            for (int u = 0; u < rgb.width; ++u) {
                sum += pt.layers.final.at(u, v, ch);
                var += double(pt.std_error.final.at(u, v, ch)) * pt.std_error.final.at(u, v, ch);
            }
        }
        say("final %c: image sum %.6g, standard error %.3g %%\n", "RGB"[ch], sum,
            sum > 0.0 ? 100.0 * std::sqrt(var) / sum : 0.0);
    }
    if (!a.layers.empty()) {
        const std::vector<std::string> rgb_names{"R", "G", "B"};
        const Layers& l = pt.layers;
        const Layers& e = pt.std_error;
        const ImageMetadata meta{{"deepsea:reference", "path tracer"},
                                 {"deepsea:paths", std::to_string(a.paths.paths)},
                                 {"deepsea:seed", std::to_string(a.paths.seed)},
                                 {"deepsea:orders", std::to_string(a.paths.min_order) + ".." +
                                                        std::to_string(a.paths.max_order)},
                                 {"deepsea:pixel_filter", a.paths.box_filter ? "box" : "centre"}};
        write_exr_layers(a.layers,
                         {{"final", &l.final, rgb_names},
                          {"direct", &l.direct, rgb_names},
                          {"forward", &l.forward, rgb_names},
                          {"backscatter", &l.backscatter, rgb_names},
                          {"transmission", &l.transmission, rgb_names},
                          {"depth", &l.depth, {"Z"}},
                          {"normal", &l.normal, {"X", "Y", "Z"}},
                          {"final_se", &e.final, rgb_names},
                          {"direct_se", &e.direct, rgb_names},
                          {"forward_se", &e.forward, rgb_names},
                          {"backscatter_se", &e.backscatter, rgb_names}},
                         meta);
        say("wrote %s\n", a.layers.c_str());
    }
    if (!a.output.empty()) write_exposed(a.output, exposure, pt.layers.final);
}

void run(const ReferenceArgs& a) {
    if (a.layers.empty() && a.output.empty()) {
        throw ConfigError("nothing to write: give --layers out.exr and/or -o out.png");
    }
    const Exposure exposure = parse_exposure(a.exposure);
    ReferenceOptions opt;
    opt.quadrature.rel_tol = a.rel_tol;
    opt.open_water_z = a.z_max;
    validate(opt.quadrature);  // a tolerance without a work bound is refused before reading
    const bool multiple = a.scattering == "multiple";
    if (!multiple && a.scattering != "single")
        throw ConfigError("--scattering: '" + a.scattering + "' is neither single nor multiple");
    // Outputs replace neither an input nor each other.
    auto others = a.setup.inputs();
    others.emplace_back(a.rgb, "the input --rgb");
    others.emplace_back(a.depth_path, "the input --depth");
    for (const std::string* out : {&a.output, &a.layers}) {
        if (!out->empty()) require_distinct(*out, others);
    }
    if (!a.output.empty() && !a.layers.empty())
        require_distinct(a.layers, {{a.output, "the -o output"}});
    if (!a.output.empty()) require_writable_image(a.output);
    if (!a.layers.empty()) require_writable_image(a.layers, /*exr_only=*/true);
    Setup setup = a.setup.load();
    require_complete(setup, "deepsea reference");
    if (multiple) {
        refuse_port(setup, "deepsea reference --scattering multiple",
                    "the path tracer through a port is not built (the single-scattering "
                    "reference traces the port's rays)");
    }
    if (setup.port) check_port_sees_input(*setup.port, *setup.camera);  // before any reading
    const Image rgb = read_color(a.rgb);
    Image depth = read_depth(a.depth_path, a.depth.read_options());
    require_same_size(rgb, depth, a.rgb + " and " + a.depth_path);
    to_planar_depth(*setup.camera, depth, a.depth.depth_kind());
    if (multiple) {
        validate(a.paths, long(rgb.width) * rgb.height);
        run_multiple(a, setup, rgb, depth, exposure);
        return;
    }

    // Through a port: the layers are water-side radiance (with the mask), as render's; -o is
    // the radiance that reaches the camera, the final layer times the port's radiance factor.
    opt.port = setup.port;
    const Layers layers =
        render_reference(*setup.camera, *setup.rig, *setup.water, rgb, depth, opt, {a.threads});
    if (!a.layers.empty()) {
        write_layers(a.layers, layers);
        say("wrote %s\n", a.layers.c_str());
    }
    if (!a.output.empty()) {
        write_exposed(a.output, exposure,
                      setup.port ? radiance_at_camera(layers.final, *setup.port, *setup.camera)
                                 : layers.final);
    }
}

}  // namespace

void setup_reference(CLI::App& sub) {
    auto a = std::make_shared<ReferenceArgs>();
    a->setup.add_to(sub);
    a->depth.add_to(sub);
    sub.add_option("--rgb", a->rgb, "in-air colour image (8/16-bit sRGB or float linear)")
        ->required();
    sub.add_option("--depth", a->depth_path, "depth image (EXR, 16-bit PNG, PFM, .npy)")
        ->required();
    sub.add_option("--layers", a->layers,
                   "multi-layer EXR with final/direct/forward/backscatter/...");
    sub.add_option("-o,--output", a->output, "exposed image (PNG, JPEG, EXR)");
    sub.add_option("--exposure", a->exposure, "'auto' or a factor applied to radiance");
    sub.add_option("--z-max", a->z_max,
                   "planar depth where open-water rays end (0: until negligible)")
        ->check(CLI::NonNegativeNumber);
    sub.add_option("--rel-tol", a->rel_tol, "relative tolerance of the backscatter quadrature")
        ->check(CLI::PositiveNumber);
    sub.add_option("--scattering", a->scattering,
                   "single (exact quadrature) or multiple (all orders: the path tracer)")
        ->check(CLI::IsMember({"single", "multiple"}));
    sub.add_option("--paths", a->paths.paths, "multiple: camera paths per pixel")
        ->check(CLI::PositiveNumber);
    sub.add_option("--seed", a->paths.seed, "multiple: random seed");
    sub.add_option("--min-order", a->paths.min_order,
                   "multiple: fewest interactions counted (2: what single scattering leaves out)")
        ->check(CLI::PositiveNumber);
    sub.add_option("--max-order", a->paths.max_order,
                   "multiple: most interactions counted (1: single scattering)")
        ->check(CLI::PositiveNumber);
    sub.add_flag("--box-filter", a->paths.box_filter,
                 "multiple: rays through the whole pixel square instead of its centre");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
