#pragma once
/// \file A baked backscatter asset in memory (docs/asset-format.md):
/// what was baked (BakeInfo) and the cumulative RGB radiance B(i, j, k) in flat arrays.
/// No OpenVDB here: the runtime reads this header only; asset_file.h does the file.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "deepsea/asset/lattice.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/forward_transport.h"
#include "deepsea/optics/lamp_field.h"
#include "deepsea/optics/light.h"
#include "deepsea/optics/port.h"
#include "deepsea/optics/water.h"

namespace deepsea {

/// The asset format this library writes and the newest it reads (`deepsea:format`). 2: every
/// grid's transform lies within the frustum's extent, the backscatter grid carries its
/// camera-space geometry as metadata (format 1's are read the same way: only the transforms
/// and the preview differ, which the loader does not use).
inline constexpr int kAssetFormat = 3;

/// Which light the backscatter values hold.
enum class Scattering {
    Single,    ///< the paper's model: light scattered once, exact
    Multiple,  ///< all orders: exact single scattering plus Monte Carlo for orders >= 2
};
/// "single" / "multiple"
const char* to_string(Scattering s);
/// Inverse of to_string; throws ConfigError naming the known values.
Scattering parse_scattering(const std::string& name);

/// The bake's own check of orders >= 2 (bake/higher_orders_check.h): the interpolated Monte
/// Carlo columns against a direct estimate with more paths at columns it did not compute.
struct HigherOrderCheck {
    bool done = false;            ///< false: not checked (--no-check, or baked before the check)
    double mean_rel = 0.0;        ///< |interpolated - direct| / all-order total, mean over columns
    double max_rel = 0.0;         ///< and worst column (worst channel and depth of each)
    double max_u = 0, max_v = 0;  ///< where the worst is, pixels (half pixels between columns)
    long columns = 0;             ///< test columns
    int paths = 0;                ///< paths of each direct estimate
    double rel_std_error = 0;     ///< the direct estimates' mean standard error / total: the floor
};

/// Monte Carlo settings of a multiple-scattering bake, and what it measured of itself.
struct HigherOrderSettings {
    int paths = 65536;              ///< Monte Carlo paths per computed column, >= 1
    int stride = 4;                 ///< computed on every stride-th lattice column and row (and the
                                    ///< last), bilinear in between: this light is smooth in angle
    bool stride_auto = false;       ///< stride chosen by auto_ms_stride (bake/lattice_rule.h)
    std::uint64_t seed = 1;         ///< base seed; results depend on it, never on the threads
    int lamp_samples = 4096;        ///< directions per node of each lamp's scattered-light table
    double rel_std_error = 0;       ///< measured: mean over computed columns and channels of the
                                    ///< standard error at z_max / the all-order total
    double fraction = 0;            ///< measured: mean share of orders >= 2 in the total at z_max
    double lamp_rel_std_error = 0;  ///< measured: lamp tables' mean LampField::rel_std_error
    /// Angle between computed columns on the optical axis, radians (stride * step / min(fx,
    /// fy)); 0: baked before the angular rule (an automatic stride was 64 px / step).
    double spacing_rad = 0;
    /// true: each depth sample but the last holds the water light in front of an absorbing
    /// wall there (MonteCarlo::wall); false: water without walls (baked before the wall model)
    bool wall = false;
    /// Tail pooling (docs/ms-columns.md): each path's light above tail_above x the column's
    /// single scattering (per channel, at z_max) is shared among the computed columns within
    /// tail_radius of it. 0: not pooled (baked before it, or a fixed model).
    double tail_above = 0;
    int tail_radius = 0;
    /// With tail pooling: the threshold is also at least tail_of_mean x the column's own
    /// orders >= 2 (per channel, at z_max), so that only paths bright for that column are
    /// pooled where single scattering is negligible. 0: baked before it (single scattering).
    double tail_of_mean = 0;
    /// true: orders >= 2 between computed columns are bilinear in their logarithm where the
    /// four columns are positive (MsColumns::log); false: bilinear (baked before it).
    bool log_between = false;
    /// true: the lamp tables' coefficients odd about each node's half-plane are 0
    /// (LampFieldSettings::symmetric); false: as estimated (baked before it).
    bool lamp_symmetric = false;
    /// true: Russian roulette comes after each path segment's next event, which then carries
    /// the path's weight before the roulette (Transport::scattered_contributions); false: before
    /// it (baked before the change: heavier tails, the same expected value).
    bool roulette_after_next_event = false;
    HigherOrderCheck check;  ///< the bake's check of the interpolation
};

/// What the bake's own accuracy check measured (bake/accuracy.h, check_lattice): the lookup
/// against exact per-pixel single-scattering integration on a sample of pixels, before the
/// values are stored (half storage adds its own floor, docs/asset-format.md).
struct LatticeCheck {
    bool done = false;            ///< false: baked with --no-check (or before the check existed)
    double mean_rel = 0.0;        ///< mean over the test pixels, worst scene
    double max_rel = 0.0;         ///< worst test pixel, any scene
    int max_u = 0, max_v = 0;     ///< where it is
    double columns_mean_rel = 0;  ///< the same on test pixels that are lattice columns: depth
    double columns_max_rel = 0;   ///< interpolation only (and the quadrature)
    long pixels = 0;              ///< test pixels (each tried in every scene)
    int refinements = 0;          ///< lattices baked and refined before this one
};

/// Everything a bake depended on, stored as the `deepsea:bake` JSON (asset_json.h).
struct BakeInfo {
    Camera camera;
    Rig rig;
    Water water;
    Lattice lattice;
    /// The housing's port the columns were baked through (docs/ports.md, "Baking through a
    /// port"): each column is its pixel's water-side ray (the green channel's), its samples at the
    /// planar depth z of points on that ray. Unset: pinhole rays from the camera centre (every
    /// asset baked before ports, which records none).
    std::optional<Port> port;
    bool z_max_auto = false;  ///< z_max was chosen by the tail tolerance, not given
    bool step_auto = false;   ///< the xy step was chosen by the baker (lattice_rule.h), not given
    bool depth_samples_auto = false;  ///< K was chosen by the baker, not given
    double tolerance = 0.0;  ///< auto z_max: tail beyond z_max / total, every column, channel
    Quadrature quadrature;   ///< accuracy of the exact integrals at bake time
    Scattering scattering = Scattering::Single;
    HigherOrderSettings higher_orders;  ///< Multiple only
    LatticeCheck check;                 ///< the bake's own accuracy check
    std::string baker_version;          ///< the bake module that made it (kBakerVersion)
    std::string input_hash;             ///< input_hash(*this) at bake time: "fnv1a64:<16 hex>"
};

/// Cumulative single-scattering backscatter on the lattice: values[index(i, j, k) + c] is
/// channel c (R, G, B) of the radiance collected along column (i, j)'s ray from the camera to
/// planar depth z[k], in the units of the rig's intensities (W/(m^2 sr) for W/sr lamps).
struct Asset {
    BakeInfo info;
    std::vector<float> values;  ///< 3 * ni * nj * nk floats, interleaved RGB
    /// Multiple scattering: the scattered light around each lamp of info.rig (same order),
    /// per unit intensity; lamps with the same intensity profile share equal tables. Empty for
    /// single scattering.
    std::vector<LampField> lamp_fields;
    /// The camera-side forward scatter from transport (optics/forward_transport.h), baked with
    /// multiple scattering where the water's forward scatter is the phase function's; absent
    /// (older assets, single scattering): the runtime uses the small-angle model.
    std::optional<ForwardPsfTable> forward_psf;

    const Lattice& lattice() const { return info.lattice; }
    /// Offset of (i, j, k)'s red value: depth fastest, then row j, then column i (OpenVDB's
    /// dense z-y-x layout, so a column's samples are contiguous).
    std::size_t index(int i, int j, int k) const {
        const Lattice& l = info.lattice;
        return ((std::size_t(i) * l.nj + j) * l.nk() + k) * 3;
    }
    Rgb at(int i, int j, int k) const {
        const float* p = values.data() + index(i, j, k);
        return {p[0], p[1], p[2]};
    }
    /// Allocates values for the lattice, zero-filled.
    void allocate();

    /// Backscatter of the ray through image point (u, v) (pixel coordinates of the asset's
    /// camera) up to planar depth z: bilinear in (u, v) between columns (clamped to the
    /// lattice), linear in z between samples, B(z_max) for z >= z_max, +inf or NaN (open
    /// water), 0 for z <= 0. This is the runtime's lookup; the accuracy tables measure it.
    Rgb sample(double u, double v, double z) const;
};

/// Throws AssetError naming both unless the frames' port refracts as the asset's (same_rays):
/// both none, or the same port. A pinhole asset with a port is accepted only where
/// `pinhole_with_port` (the runtime's approximate lookup, runtime/port_backscatter.h).
void check_port(const Asset& asset, const std::optional<Port>& port, bool pinhole_with_port);

/// Throws AssetError naming both cameras unless `camera` equals the asset's camera or has the
/// same view at another resolution (check_same_view; the runtime then resamples).
void check_camera(const Asset& asset, const Camera& camera);

}  // namespace deepsea
