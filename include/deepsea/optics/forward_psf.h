#pragma once
/// \file Camera-side forward scatter derived from the phase function (docs/model.md, "Forward
/// scatter"). Light leaving a surface at distance d reaches the camera after n small-angle
/// scatterings with weight exp(-c d) (b d)^n / n!, spread over the image by the angular kernel
/// K_n, the n-fold convolution of
///     K_1(psi) = (1 / psi) * integral_psi^{pi/2} p(theta) sin(theta) / theta dtheta   (1/sr):
/// a scattering by theta at a uniformly distributed point of the path is seen from the camera
/// at psi = theta u, u uniform in [0, 1]. Each K_n is held as a mixture of Gaussians of fixed
/// widths, so a renderer blurs a few weighted images with fixed Gaussians.

#include <vector>

#include "deepsea/core/vec.h"
#include "deepsea/optics/phase.h"

namespace deepsea {

struct Water;
struct ForwardPsfTable;

/// The angular kernels K_1 .. K_N of one phase function as Gaussian mixtures on a fixed grid of
/// widths (radians) a factor 2^(1/4) apart.
struct ForwardSpread {
    std::vector<double> sigma;              ///< radians, ascending
    std::vector<std::vector<double>> mass;  ///< mass[n - 1][j]: K_n's weight on sigma[j]
};

/// Highest scattering order kept (b d up to about 200; beyond, exp(-c d) has long underflowed
/// in any water deepsea accepts).
constexpr int kForwardOrders = 256;

/// K_1(psi) in 1/sr, psi in radians (0 beyond pi/2: light scattered backwards leaves the
/// surface's side of the camera).
double forward_kernel(const Phase& phase, double psi);

/// Share of K_1 within psi of its centre, 2 pi integral_0^psi t K_1(t) dt; at pi/2 it is the
/// phase function's forward-hemisphere fraction.
double forward_kernel_within(const Phase& phase, double psi);

/// Mixtures of K_1 .. K_orders; mass[n - 1] sums to forward_kernel_within(pi/2)^n.
ForwardSpread forward_spread(const Phase& phase, int orders = kForwardOrders);

/// Share of a Gaussian mixture within psi of its centre (for checks of the mixtures).
double mixture_within(const std::vector<double>& sigma, const std::vector<double>& mass,
                      double psi);

/// The point spread in pixels for one camera and water: scale 0 leaves the light where it is,
/// scale j >= 1 is a Gaussian of sigma_px(j) = 2^(j-1) pixels, the last capped at the image's
/// larger side. weight(j, d) is the share of a surface's radiance (J/pi E) at distance d that
/// reaches the camera spread by scale j, per channel; summed over j it is about
/// exp(-c d) (exp(f b d) - 1), f the forward fraction. The reference renderer and the runtime
/// both blur with these scales and weights.
class ForwardPsf {
public:
    ForwardPsf(const Water& water, double fx, int width, int height);
    /// The same scales with weights from a transport table (forward_transport.h), fitted per
    /// table depth: each ring share's mixture on the angular widths (expectation-maximisation,
    /// as K_1's), then placed on the pixel scales; linear in distance between the table's
    /// depths, 0 at the camera, and beyond the last depth falling as the total did over the
    /// last step. ConfigError if the table is malformed.
    ForwardPsf(const ForwardPsfTable& table, const Water& water, double fx, int width, int height);

    /// Whether the weights come from a transport table (else: the small-angle model).
    bool from_transport() const { return m_table; }
    /// Transport tables only: the largest difference, over depths, channels and ring edges
    /// below pi/2, between the fitted mixture's enclosed share and the table's, relative to the
    /// depth's total scattered share.
    double fit_error() const { return m_fit_error; }

    int scales() const { return int(m_sigma_px.size()); }
    double sigma_px(int j) const { return m_sigma_px[j]; }
    Rgb weight(int j, double d) const;
    /// Sum of weight(j, d) over every scale.
    Rgb total(double d) const;
    /// A distance beyond which every weight is below 1e-17 (the total decays at least as
    /// exp(-(c - f b) d), f the forward fraction < 1).
    double negligible_beyond() const;

private:
    Rgb m_c, m_b;
    double m_forward = 0.0;  ///< forward-hemisphere fraction f
    std::vector<double> m_sigma_px;
    std::vector<std::vector<double>> m_mass;  ///< m_mass[n - 1][j]: order n on pixel scale j
    bool m_table = false;                     ///< weights from a transport table
    std::vector<double> m_node;               ///< the table's depths, metres
    std::vector<Rgb> m_node_weight;           ///< [k * scales() + j]: scale j at depth k
    Rgb m_tail_rate;                          ///< 1/m: fall of the weights beyond the last depth
    double m_fit_error = 0.0;
};

}  // namespace deepsea
