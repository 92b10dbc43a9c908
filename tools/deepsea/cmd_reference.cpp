// deepsea reference: exact per-pixel rendering (no asset), the ground truth.

#include <cstdio>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/io/image_io.h"
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
};

void run(const ReferenceArgs& a) {
    if (a.layers.empty() && a.output.empty()) {
        throw ConfigError("nothing to write: give --layers out.exr and/or -o out.png");
    }
    const Exposure exposure = parse_exposure(a.exposure);
    ReferenceOptions opt;
    opt.quadrature.rel_tol = a.rel_tol;
    opt.open_water_z = a.z_max;
    validate(opt.quadrature);  // a tolerance without a work bound is refused before reading
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
    const Image rgb = read_color(a.rgb);
    Image depth = read_depth(a.depth_path, a.depth.read_options());
    require_same_size(rgb, depth, a.rgb + " and " + a.depth_path);
    to_planar_depth(*setup.camera, depth, a.depth.depth_kind());

    const Layers layers =
        render_reference(*setup.camera, *setup.rig, *setup.water, rgb, depth, opt, {a.threads});
    if (!a.layers.empty()) {
        write_layers(a.layers, layers);
        say("wrote %s\n", a.layers.c_str());
    }
    if (!a.output.empty()) {
        const double f = exposure_factor(exposure, layers.final);
        write_color(a.output, apply_exposure(layers.final, f));
        say("wrote %s (exposure %.6g)\n", a.output.c_str(), f);
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
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
