// deepsea info: what an asset holds, for a person (or --json for scripts).

#include <algorithm>
#include <cstdio>
#include <string>

#include "cli_util.h"
#include "commands.h"
#include "deepsea/asset/asset_file.h"
#include "deepsea/asset/asset_json.h"
#include "deepsea/core/error.h"
#include "deepsea/core/parallel.h"
#include "deepsea/optics/forward_lean.h"

namespace deepsea::cli {

namespace {

struct InfoArgs {
    std::string path;
    bool json = false;
    int threads = 0;
};

void run(const InfoArgs& a) {
    const AssetFileSummary s = read_asset_summary(a.path);
    Asset asset;
    in_arena(a.threads, [&] { asset = load_asset(a.path); });  // also checks the voxel data
    const BakeInfo& b = s.info;
    const Lattice& l = b.lattice;
    if (a.json) {
        std::printf("%s\n", asset_info_json(a.path, s, asset).c_str());
        return;
    }
    const auto [lo, hi] = backscatter_range(asset);
    const Camera& c = b.camera;
    std::printf("asset      %s (%.2f MB, format %d)\n", a.path.c_str(), s.file_bytes / 1e6,
                s.format);
    std::printf("camera     %dx%d fx=%g fy=%g cx=%g cy=%g\n", c.width, c.height, c.fx, c.fy, c.cx,
                c.cy);
    // Baked along the port's water-side rays (docs/ports.md), or along pinhole rays.
    std::printf("port       %s\n",
                b.port ? (describe(*b.port) + ": columns along its water-side rays").c_str()
                       : "none (pinhole rays from the camera centre)");
    std::printf("rig        %s, %zu lamp(s)\n", b.rig.name.c_str(), b.rig.lights.size());
    for (const Light& L : b.rig.lights) {
        char rid[64] = "table RID";
        if (L.rid.kind == Rid::Kind::Gaussian) {
            std::snprintf(rid, sizeof rid, "gaussian sigma %g deg", L.rid.sigma_deg);
        }
        std::printf(
            "  %-8s at (%g, %g, %g) m, axis (%.4f, %.4f, %.4f), I (%g, %g, %g) W/sr, %s, radius "
            "%g m\n",
            L.name.c_str(), L.position.x, L.position.y, L.position.z, L.direction.x, L.direction.y,
            L.direction.z, L.intensity.r, L.intensity.g, L.intensity.b, rid, L.radius);
    }
    const Water& w = b.water;
    std::printf("water      %s: c (%g, %g, %g) 1/m, b (%g, %g, %g) 1/m, phase %s", w.name.c_str(),
                w.c.r, w.c.g, w.c.b, w.b.r, w.b.g, w.b.b, to_string(w.phase.kind));
    if (w.phase.kind == PhaseKind::HenyeyGreenstein) std::printf(" g=%g", w.phase.g);
    if (w.forward.enabled && w.forward.model == ForwardModel::PhaseFunction) {
        std::printf(", forward scatter from the phase function");
    } else if (w.forward.enabled) {
        std::printf(", forward scatter G (%g, %g, %g) k %g rad/m", w.forward.G.r, w.forward.G.g,
                    w.forward.G.b, w.forward.k);
    } else {
        std::printf(", forward scatter off");
    }
    std::printf(
        "\nlattice    %d x %d columns, step %d px%s; %d depth samples%s (%s), z 0 .. %.3f m%s\n",
        l.ni, l.nj, l.step, b.step_auto ? " (auto)" : "", l.nk(),
        b.depth_samples_auto ? " (auto)" : "", to_string(l.scheme), l.z_max(),
        b.z_max_auto ? " (auto)" : "");
    std::printf("values     backscatter at z_max: R %.4g..%.4g, G %.4g..%.4g, B %.4g..%.4g\n", lo.r,
                hi.r, lo.g, hi.g, lo.b, hi.b);
    if (b.scattering == Scattering::Multiple) {
        const HigherOrderSettings& h = b.higher_orders;
        std::printf(
            "scattering multiple: single exact + orders >= 2 by Monte Carlo (%d paths on "
            "every %d-th column, seed %llu): %.1f %% of the light, standard error "
            "%.2f %% of the total\n",
            h.paths, h.stride, static_cast<unsigned long long>(h.seed), 100.0 * h.fraction,
            100.0 * h.rel_std_error);
        if (h.spacing_rad > 0.0) {
            std::printf("           columns %.2f deg apart on the axis (%s)\n",
                        h.spacing_rad * 57.29577951308232,
                        h.stride_auto ? "from the light's angular detail" : "--ms-stride");
        } else {
            std::printf(
                "           columns every %d-th lattice column (%d px; baked before the "
                "angular rule)\n",
                h.stride, h.stride * l.step);
        }
        std::printf("           between columns: %s\n",
                    h.log_between ? "bilinear in the logarithm (geometric) where positive"
                                  : "bilinear (baked before log-bilinear)");
        std::printf("           %s\n",
                    h.wall ? "in front of a surface: orders >= 2 with an absorbing wall at its "
                             "depth (open water: without walls)"
                           : "in front of a surface: water without walls (baked before the "
                             "wall model)");
        if (h.tail_above > 0.0 && h.tail_of_mean > 0.0) {
            std::printf(
                "           bright paths pooled: light above %g x a column's single scattering "
                "and %g x its own orders >= 2 shared within %d computed columns\n",
                h.tail_above, h.tail_of_mean, h.tail_radius);
        } else if (h.tail_above > 0.0) {
            std::printf(
                "           bright paths pooled: light above %g x a column's single scattering "
                "shared within %d computed columns\n",
                h.tail_above, h.tail_radius);
        } else {
            std::printf("           each column from its own paths (baked before tail pooling)\n");
        }
        std::printf("           %s\n",
                    h.roulette_after_next_event
                        ? "paths: Russian roulette after each segment's next event"
                        : "paths: Russian roulette before each segment's next event (baked "
                          "before the change: heavier tails)");
        if (h.check.done) {
            std::printf(
                "           check of orders >= 2: mean %.2f %%, max %.2f %% of the total "
                "at pixel (%g, %g), on %ld columns between computed ones (%d paths each, "
                "their standard error %.2f %%)\n",
                100.0 * h.check.mean_rel, 100.0 * h.check.max_rel, h.check.max_u, h.check.max_v,
                h.check.columns, h.check.paths, 100.0 * h.check.rel_std_error);
        } else {
            std::printf("           orders >= 2 not checked\n");
        }
        std::printf(
            "           scattered lamp light at surfaces: %zu lamp table(s), %d directions "
            "per node, standard error %.2f %% (facing the lamp, mean over nodes)%s\n",
            b.rig.lights.size(), h.lamp_samples, 100.0 * h.lamp_rel_std_error,
            h.lamp_symmetric ? ", mirror-symmetric about each node's half-plane" : "");
    } else {
        std::printf("scattering single (the paper's model, exact)\n");
    }
    if (w.forward.enabled && w.forward.model == ForwardModel::PhaseFunction) {
        if (const auto& t = asset.forward_psf) {
            // the worst depth's standard error relative to its scattered light
            double se = 0.0;
            for (int k = 0; k < t->depths(); ++k) {
                for (int ch = 0; ch < 3; ++ch) {
                    const double total = t->total(k)[ch];
                    if (total > 0.0) se = std::max(se, t->std_error[k][ch] / total);
                }
            }
            std::printf(
                "forward    from transport, all orders: %d plane depths to %.2f m, %d rings of "
                "angle, %d paths (seed %llu), standard error up to %.2f %% of the scattered "
                "light\n",
                t->depths(), t->depth.back(), t->rings(), t->paths,
                static_cast<unsigned long long>(t->seed), 100.0 * se);
            // the runtime's, not the asset's: every transport table gets it (not through a port)
            std::printf(
                "           tilted surfaces: the kernel leans to the near side, 1 + "
                "(rho - 1) tan(alpha) psi, rho %g (derived, not baked)\n",
                double(kForwardLeanRho));
        } else {
            std::printf("forward    small-angle model (no transport table in this asset)\n");
        }
    }
    std::printf("check      %s\n", describe_check(b).c_str());
    std::printf("bake       tolerance %g, quadrature rel %g, %s, inputs %s\n", b.tolerance,
                b.quadrature.rel_tol, b.baker_version.c_str(), b.input_hash.c_str());
    for (const GridSummary& g : s.grids) {
        std::printf("grid       %-12s %-6s %-8s %s%lld active voxels\n", g.name.c_str(),
                    g.value_type.c_str(), g.transform.c_str(), g.half ? "half, " : "",
                    static_cast<long long>(g.active_voxels));
    }
    if (s.preview_voxel_size > 0.0) {
        std::printf("preview    %.1f mm voxels (density 1 = in-scatter luminance %.4g per metre)\n",
                    1e3 * s.preview_voxel_size, s.preview_density_scale);
    }
}

}  // namespace

void setup_info(CLI::App& sub) {
    auto a = std::make_shared<InfoArgs>();
    sub.add_option("asset", a->path, "asset file (.vdb)")->required();
    sub.add_flag("--json", a->json, "print JSON for scripts");
    add_threads(sub, a->threads);
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
