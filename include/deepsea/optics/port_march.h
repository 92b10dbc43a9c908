#pragma once
/// \file The march of optics/port_hit.h (march_port_ray), in the header so that the runtime's
/// float rows inline it. Include port_hit.h, not this.

#include "deepsea/optics/port_hit.h"

namespace deepsea {

namespace port_detail {

template <class T>
struct Tolerance;
template <>
struct Tolerance<double> {
    static constexpr double value = kPortHitTolerance;
    static constexpr double span = 1e-15;  ///< the smallest bracket, relative to its s
};
template <>
struct Tolerance<float> {
    static constexpr float value = kPortHitToleranceFloat;
    static constexpr float span = 4 * std::numeric_limits<float>::epsilon();
};

/// The ray at inverse depth s against the surface: h = s - 1 / z_surface, > 0 in front of it
/// (the surface is deeper), <= 0 on or behind it. Open water (count 0) is in front at any s.
template <class T>
struct Probe {
    T s = 0, h = 0, inv_z = 0;
    int count = 0;  ///< surface_taps' count
    bool open() const { return count == 0; }
    bool front() const { return count == 0 || h > 0; }
};

template <class T>
struct Marcher {
    const Image& inv;
    const PortMarch<T>& ray;
    SurfaceTapsT<T>& taps;  ///< the taps of the refinement's last probe,
    T& taps_s;              ///< at this s

    Probe<T> at(T s) const {
        T inv_z;
        const int count =
            taps_at<T, false>(inv, ray.u_inf + ray.du * s, ray.v_inf + ray.dv * s, inv_z, nullptr);
        return {s, s - inv_z, inv_z, count};
    }

    /// at(s) that also writes its taps to `taps` (in place: a struct assembled and then copied
    /// stalls the loads that read it).
    Probe<T> at_with_taps(T s) const {
        taps.count = taps_at<T, true>(inv, ray.u_inf + ray.du * s, ray.v_inf + ray.dv * s,
                                      taps.inv_z, &taps);
        taps_s = s;
        return {s, s - taps.inv_z, taps.inv_z, taps.count};
    }

    /// The crossing between a (in front) and b (behind, b.s < a.s): Illinois steps (bisection
    /// while a is open water, whose h says nothing of distance). Returns the crossing and
    /// whether the surface is continuous across it (not a depth edge).
    Probe<T> refine(Probe<T> a, Probe<T> b, bool& continuous) const {
        const T tol = Tolerance<T>::value, rate = ray.rate;
        Probe<T> best = b;
        int side = 0;
        continuous = false;
        for (int it = 0; it < 200 && b.h != 0; ++it) {
            T s = a.open() ? T(0.5) * (a.s + b.s) : (a.s * b.h - b.s * a.h) / (b.h - a.h);
            if (!(s < a.s && s > b.s)) s = T(0.5) * (a.s + b.s);
            const Probe<T> c = at_with_taps(s);
            if (c.front()) {
                a = c;
                if (side == 1) b.h *= T(0.5);
                side = 1;
            } else {
                b = c;
                if (side == -1 && !a.open()) a.h *= T(0.5);
                side = -1;
            }
            best = c;
            if (!c.open() && std::fabs(c.h) <= tol * (c.s + c.inv_z)) {
                // on the surface, between four pixels of one surface: no edge here
                if (c.count == 4) {
                    continuous = true;
                    return c;
                }
                break;
            }
            if ((a.s - b.s) * rate <= tol || a.s - b.s <= Tolerance<T>::span * a.s) {
                best = b;
                break;
            }
        }
        if (b.h == 0) best = b;
        // Across the crossing, a thousandth of a pixel either way: one surface, or an edge.
        const T ds = std::min(T(1e-3) / rate, T(1e-3) * best.s);
        const Probe<T> n = at(best.s + ds), f = at(std::max(best.s - ds, T(0)));
        const T lo = std::min(n.inv_z, f.inv_z), hi = std::max(n.inv_z, f.inv_z);
        continuous = !n.open() && !f.open() && hi - lo <= T(kDepthDiscontinuity) * lo;
        return best;
    }
};

}  // namespace port_detail

template <class T>
PortCrossing<T> march_port_ray(const Image& inv, const PortMarch<T>& ray, T s_near) {
    using Probe = port_detail::Probe<T>;
    PortCrossing<T> hit;
    if (!(ray.s_origin > 0)) return hit;  // not forward: sees nothing
    // Nothing is nearer than the frame's nearest surface; the ray exists from its origin on.
    T hi = std::min(ray.s_origin, s_near);
    if (!(hi < std::numeric_limits<T>::infinity())) hi = T(1e3);  // (from 1 mm on)
    hi = std::min(hi, ray.s_hi);
    const T lo = ray.s_lo;
    if (!(lo <= hi)) return hit;  // never inside the input's view
    // the s of the refinement's last probe, whose taps are in hit.taps (-1: none yet)
    T taps_s = -1;
    const port_detail::Marcher<T> m{inv, ray, hit.taps, taps_s};
    // (the hit is written in place: a struct assembled and then copied stalls the loads)
    const auto surface = [&](T s) {
        hit.kind = PortHitKind::Surface;
        hit.s = s;
        hit.u = ray.u_inf + ray.du * s;
        hit.v = ray.v_inf + ray.dv * s;
        hit.taps.count =
            port_detail::taps_at<T, true>(inv, hit.u, hit.v, hit.taps.inv_z, &hit.taps);
    };
    Probe prev = m.at(hi);
    if (!prev.open() && prev.h == 0) {
        surface(prev.s);
        return hit;
    }
    if (!prev.front()) return hit;  // enters the view behind a surface
    const T span = hi - lo;
    if (span * ray.rate < T(kPortStillPx)) {
        // The projection stands still: the surface under it, S, is met at s = S if the ray
        // reaches it in view (S >= lo; S < hi, as the ray is in front of it at hi).
        if (prev.open()) {
            if (lo == 0) hit.kind = PortHitKind::OpenWater;
            return hit;
        }
        if (prev.inv_z < lo) return hit;
        // S read where the projection lies at s = S (the ray's own crossing, to the surface's
        // change over the projection's sub-hundredth of a pixel times its own, a second time)
        const Probe at_s = m.at(prev.inv_z);
        if (at_s.open() || at_s.inv_z < lo) return hit;
        surface(at_s.inv_z);
        return hit;
    }
    const int steps = int(std::clamp(std::ceil(span * ray.rate), T(1), T(65536)));
    const T step = span / T(steps);
    bool behind_edge = false;
    for (int i = 1; i <= steps; ++i) {
        const Probe cur = m.at(i == steps ? lo : hi - step * T(i));
        if (prev.front() && !cur.front()) {
            bool continuous = false;
            const Probe x = m.refine(prev, cur, continuous);
            if (continuous) {
                if (x.s == taps_s) {
                    // the crossing is the refinement's last probe: its taps are in place
                    hit.kind = PortHitKind::Surface;
                    hit.s = x.s;
                    hit.u = ray.u_inf + ray.du * x.s;
                    hit.v = ray.v_inf + ray.dv * x.s;
                    return hit;
                }
                surface(x.s);
                return hit;
            }
            behind_edge = true;  // passes behind a foreground edge: look beyond it
        }
        prev = cur;
    }
    // No crossing: open water if the whole ray to its vanishing point was in view.
    if (!behind_edge && prev.front() && lo == 0) hit.kind = PortHitKind::OpenWater;
    return hit;
}

}  // namespace deepsea
