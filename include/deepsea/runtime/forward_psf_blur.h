#pragma once
/// \file The runtime's forward scatter from the phase function (optics/forward_psf.h):
/// F = sum_j G_j * (W_j(d) L_s), a fixed Gaussian per scale j applied to the surface radiance
/// weighted by that scale's share at each pixel's distance. Wide scales are summed into
/// box-downsampled images as they are weighted and blurred there; the blurred images are then
/// added coarse to fine, each grid upsampled by two into the next, so a full-resolution row
/// costs one upsampling whatever the number of scales. Pixels are weighed not by every scale
/// but by a few functions of distance that span the scales' weights to 1e-6 of their total
/// (their block sums give each scale's), as few as 3 in clear water; 1e-3 for weights fitted
/// to a transport table (optics/forward_transport.h), whose Monte Carlo error is larger.

#include <algorithm>
#include <map>
#include <vector>

#include "deepsea/core/image.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/forward_psf.h"
#include "deepsea/runtime/sources.h"

namespace deepsea {

/// What lies beyond a W x H frame for a transport table's blur: each border pixel continued
/// outward, times a factor per distance (the continued surface's weighted radiance over the
/// border pixel's; edge_falloff below computes it from the lamps). Factors at
/// dist[k] pixels beyond the edge, linear in between, 1 at the edge, the last one beyond.
/// Per channel c, border pixel i and sample k: left and right (i = row) at
/// [(c * height + i) * K + k], top and bottom (i = column) at [(c * width + i) * K + k].
struct EdgeFalloff {
    int width = 0, height = 0;
    std::vector<float> dist;  ///< pixels beyond the edge, ascending, > 0 (K values)
    std::vector<float> left, right, top, bottom;
    int samples() const { return int(dist.size()); }
    /// The factor of one side's (left, right, top or bottom) border pixel at s pixels beyond
    /// it.
    float at(const std::vector<float>& side, int border, int c, float s) const;
};

/// The falloff beyond the frame of a planar depth image `zdepth` lit by `lamps`: each border
/// pixel's surface continued outward at its planar depth and normal (the nearest border pixel's
/// albedo), its irradiance over the border pixel's (unshadowed, every lamp, scattered light
/// included), times psf's total weight at its distance over the border pixel's. Evaluated at
/// every edge_falloff_step-th border pixel and the last, linear between
/// (src/runtime/forward_psf_edges.cpp).
void edge_falloff(const Camera& cam, const Image& zdepth, const IrradianceSource& lamps,
                  const ForwardPsf& psf, EdgeFalloff& out);

/// Border pixels between two of edge_falloff's samples along a side of n pixels: 8, or an
/// eighth of the side on larger frames (the lamps' light varies slowly along a border; each
/// sample costs 13 lamp evaluations, about 1 us each with lamp fields).
inline int edge_falloff_step(int n) { return std::max(8, (n - 1 + 7) / 8); }

/// Reusable state: buffers are kept between frames. prepare() weighs and blurs one frame,
/// row() then gives any row of F as an interleaved RGB row (thread-safe).
class ForwardPsfBlur {
public:
    /// c: the water's beam attenuation (1/m), for add_direct_row's transmission.
    explicit ForwardPsfBlur(ForwardPsf psf, const Rgb& c = {});

    /// surface: J/pi E (3 channels); d2: camera-to-surface distance (1 channel, <= 0 for no
    /// surface, which sends no light; finite: NaN and inf are sanitised first, as the
    /// compositor does, or the rows' float-to-int conversions and the farthest distance found
    /// here are undefined). Both are read again by row(): they must stay unchanged until the
    /// frame's rows are taken. beyond (transport tables only, may be null: the borders
    /// continued unchanged): how the scene dims beyond the frame, of this frame's size.
    /// farthest: d2's largest value where the caller has it (the compositor, from its rows:
    /// no pass over d2 here), < 0 to have it found here. lean (transport tables only, may be
    /// null: no lean): 2 channels, each pixel's kernel lean (lu, lv) in 1/px
    /// (optics/forward_lean.h): F at p gathers sum_q K(p - q) (1 + l_p . (q - p)) W L(q), added
    /// as l_p . grad M(p), M = sum_j sigma_j^2 (G_j * W_j L) (for a Gaussian, sum_q G(p - q)
    /// (q - p) S(q) = sigma^2 grad (G * S)(p)), held within the blurred light's own value. Only
    /// its even rows are read, unless level_factor(1, W, H) is 1 (scales blurred at full
    /// resolution, on images under 16 px a side).
    void prepare(const Image& surface, const Image& d2, const EdgeFalloff* beyond = nullptr,
                 double farthest = -1.0, const Image* lean = nullptr);
    /// out_rgb[3u + c] = F at (u, v).
    void row(int v, float* out_rgb) const;
    /// sum_rgb[3u + c] += F at (u, v): the same F as row(), added where it is wanted.
    void add_row(int v, float* sum_rgb) const;
    /// sum_rgb[3u + c] += D + F at (u, v), D = L_s exp(-c d2) the direct signal: the
    /// transmission taken from the unblurred scale's table, W_0(d) + exp(-c d) linear between
    /// its rows (docs/model.md, "Forward scatter": within 1e-4 of D), so that the image alone
    /// costs no exponential a pixel; surfaces beyond the table exactly.
    void add_direct_row(int v, float* sum_rgb) const;

    const ForwardPsf& psf() const { return m_psf; }
    /// True angles off axis (transport tables only; fx <= 0: off, the default): the grids of
    /// the scales 1/40 rad wide and wider (factor >= 4) hold the equidistant image, rho = fx
    /// atan(r / fx) along each radius, so that their Gaussians span equal angles everywhere (a
    /// pinhole pixel spans cos^2 / fx radians radially off axis, cos / fx across); the
    /// narrower scales stay in the pinhole image. Across a radius the equidistant image is
    /// theta / sin(theta) too wide (1.08 at 38 degrees). forward_psf_warp.cpp.
    void set_camera(double fx, double fy, double cx, double cy);
    /// Block distances (on by default): the finest grid's 2 x 2 blocks whose distances lie
    /// within kBlockTolerance of each other are weighed once, at their mean distance, instead
    /// of pixel by pixel (docs/model.md, "Forward scatter": within one 8-bit code and 0.1 % of
    /// the forward layer's maximum). Off: every pixel at its own distance (the exact path the
    /// tests compare with).
    void set_block_distances(bool on) { m_block_tol = on ? kBlockTolerance : -1.0f; }
    /// Unblurred fine scales (on by default): a scale whose Gaussian on its grid is narrower
    /// than planes::kIdentitySigma (the 1 px scale: 0.15 cells, its taps beside the centre
    /// 2.3e-10 of its weight) is added to its grid without the blur (docs/runtime.md, "Bounded
    /// approximations": within 1e-9 of the forward layer's maximum). Off: blurred (the exact path).
    void set_identity_blurs(bool on) { m_identity_blurs = on; }
    /// The scales the last prepare() added unblurred (set_identity_blurs).
    int unblurred_scales() const { return m_unblurred; }
    /// The largest spread of a block's distances, relative to its nearest, weighed at their mean.
    static constexpr float kBlockTolerance = 0.02f;
    /// The weight of scale j at distance d (m) that the last prepare() applied: its tables'
    /// interpolation, the blurred scales through their basis (zero beyond the tables).
    Rgb applied_weight(int j, double d) const;

    /// Variance (px^2) that box-downsampling by `factor` (a power of two) and upsampling back
    /// through the grids of factors factor/2, ..., 2, 1 add to a pixel's light, averaged over
    /// its place in the block.
    static double resampling_variance(int factor);
    /// Downsampling factor for a Gaussian of sigma pixels: the largest power of two whose
    /// resampling variance is within sigma^2, that keeps the smaller image at least 8 pixels
    /// high and wide, and is at most 128. Scale 1 (sigma 1 px) gets factor 2: a box of two
    /// and the upsampling back spread exactly its variance, so no scale is blurred at full
    /// resolution.
    static int level_factor(double sigma, int width, int height);

private:
    /// One grid of the cascade: the image downsampled by 2^k (k >= 1).
    struct Grid {
        int factor = 2, w = 0, h = 0;
        std::vector<float> acc;  ///< 3 planes: this grid's blurred scales + coarser grids
        std::vector<float> mom;  ///< the same times sigma_j^2 (px^2), with a lean only
    };
    /// Scales sharing one downsampling factor.
    struct Group {
        int factor = 1, j0 = 1, j1 = 1, w = 0, h = 0;
        double spent = 0.0;  ///< resampling_variance(factor)
    };
    struct Level {
        int group = 0;
        std::vector<float> planes;  ///< 3 planes at the group's grid: the weighted image
    };
    /// The distance (m) the table of ladder rung `rung` spans: 2^(rung / 4).
    static double table_span(int rung);
    /// Makes the table of `rung` current: kept from an earlier frame, or built.
    void use_table(int rung);
    void build_table(double d_max);
    Grid& grid_of(int factor);
    void resize(int W, int H);
    void weigh(const Image& surface, const Image& d2);
    /// F of row v, interleaved RGB, into out or added to it.
    void rgb_row(int v, float* out, bool add, bool direct) const;
    /// Adds the lean, l . grad M (prepare), into the finest blurred light: the factor-2 grid's
    /// cells (each block's mean lean, M's differences between cells) and the scales blurred at
    /// full resolution (forward_psf_lean.cpp). The lean is smooth where it matters (M is the
    /// blurred light), so the grid's cells carry it as they carry the light.
    void add_lean();
    /// Adds one level's blurred planes (n floats) into a grid's acc and, times sigma^2, mom.
    static void add_level(std::size_t n, const float* blurred, float sigma2, float* acc,
                          float* mom);

    ForwardPsf m_psf;
    int m_lanes = 0;  ///< table lanes per distance: 3 channels x m_stride basis functions
    int m_stride = 0;
    int m_width = 0, m_height = 0;
    double m_step = 0.0;  ///< distance between table rows, metres
    int m_bins = 0;       ///< table rows - 1
    /// m_table[bin * lanes + c * stride + r]: basis function r of channel c at the bin's
    /// distance; W_j(d) of a blurred scale j = sum_r m_coef[(c * S + j) * stride + r] times
    /// that (column_basis.h).
    std::vector<float> m_table, m_coef;
    /// m_sharp[bin * 4 + c] = W_0(d), the unblurred scale, then (from row bins + 1 on) the
    /// same plus exp(-c d)
    std::vector<float> m_sharp;
    Rgb m_c;                              ///< the water's beam attenuation, 1/m
    float m_block_tol = kBlockTolerance;  ///< block distances' tolerance, < 0: off
    bool m_identity_blurs = true;         ///< set_identity_blurs
    int m_unblurred = 0;                  ///< unblurred_scales
    int m_rung = -1;                      ///< ladder rung of the current table (-1: none yet)
    /// Tables of other rungs that earlier frames needed, kept (a few kB each; at most one per
    /// rung up to the distance where every weight is negligible, about a hundred).
    struct KeptTable {
        double step = 0.0;
        int bins = 0, stride = 0, lanes = 0;
        std::vector<float> table, coef, sharp;
    };
    std::map<int, KeptTable> m_kept;
    const Image* m_surface = nullptr;  ///< prepare()'s frame, for scale 0 (unblurred)
    const Image* m_d2 = nullptr;
    std::vector<float> m_full;       ///< scales blurred at full resolution (tiny images): 3 planes
    std::vector<float> m_full_mom;   ///< the same times sigma_j^2, with a lean only
    const Image* m_lean = nullptr;   ///< prepare()'s lean (null: none)
    std::vector<float> m_blurred;    ///< one level's blur, with a lean
    std::vector<float> m_cell_lean;  ///< the factor-2 grid's cells' mean lean, 2 floats each
    std::vector<Group> m_groups;
    std::vector<Level> m_levels;  ///< scales 1 .. S-1
    std::vector<Grid> m_grids;    ///< factors 2, 4, .. up to the widest group's
    /// blur_planes' scratch
    std::vector<float> m_kernel, m_norm_x, m_norm_y;
    /// Fills m_fade for one grid (factor f, w x h) and kernel radius r from `beyond`.
    void fade_grid(const EdgeFalloff& beyond, int f, int w, int h, int r);
    std::vector<float> m_fade[4];  ///< left, right, top, bottom of the grid being blurred

    /// The equidistant grids (set_camera; forward_psf_warp.cpp).
    struct WarpMap {
        std::vector<float> ex, ey;  ///< each pinhole cell's place in the equidistant grid
        std::vector<float> norm;    ///< each equidistant cell's 1 / splatted weight (0: none)
        std::vector<int> margin;    ///< equidistant cells beyond the frame
    };
    double m_cam[4] = {0.0, 0.0, 0.0, 0.0};  ///< fx, fy, cx, cy (fx <= 0: no warp)
    int m_warp = 0;                          ///< the finest equidistant grid's factor (0: none)
    std::map<int, WarpMap> m_warp_maps;      ///< by factor
    std::vector<float> m_warp_x, m_warp_y;   ///< factor m_warp / 2 cells' equidistant places
    std::vector<float> m_eq;                 ///< one level's equidistant planes
    void build_warp();
    /// The pixel (u, v) (pinhole) of the equidistant point (ue, ve), and back.
    void from_equidistant(double ue, double ve, double& u, double& v) const;
    void to_equidistant(double u, double v, double& ue, double& ve) const;
    /// The level's planes (grid factor f) splatted into m_eq, the cells beyond the frame the
    /// border continued as `beyond` says (null: unchanged); returns m_eq.
    const float* warp_level(const std::vector<float>& planes, int f, int w, int h,
                            const EdgeFalloff* beyond);
    /// m_fade for group g's equidistant grid, each continued cell's falloff over the border
    /// cell's, as far as its widest scale reaches (once a frame per group); returns that reach.
    int fade_equidistant(const EdgeFalloff* beyond, int g);
    int m_faded_group = -1, m_faded_reach = 0;
    std::vector<float> m_fade_border;  ///< fade_equidistant's border cells' own falloffs
    /// Grid G (factor m_warp / 2, pinhole) += the equidistant grid above it sampled at G's cells.
    void add_unwarped(Grid& G, const Grid& coarser) const;
};

}  // namespace deepsea
