#include "deepsea/reference/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/core/random.h"
#include "deepsea/optics/backscatter.h"
#include "deepsea/optics/direct.h"
#include "deepsea/optics/lamp.h"
#include "deepsea/optics/normals.h"
#include "deepsea/optics/phase_sampling.h"
#include "deepsea/optics/transmission.h"
#include "deepsea/reference/reference.h"
#include "scene_surface.h"

// The estimator (docs/reference.md). A path starts at the camera and is extended one
// interaction at a time; every segment it follows, from a vertex to where the ray next meets
// the surface (or forever), gathers next events:
// - the light of each lamp scattered once on the segment: one sample of the distance along
//   it, equiangular about the lamp (Kulla & Fajardo 2012, "Importance sampling techniques for
//   path tracing in participating media") or in proportion to the phase function of the angle
//   it turns there (Equiangular below), so the lamp's inverse square cancels;
// - from every vertex after the camera, the same light sampled from the lamp's side: a ray
//   from the lamp, then a point on it equiangular about the vertex (lamp_side_light), which
//   keeps the estimate finite where a vertex sees a lamp's glow; both by the balance heuristic;
// - where the segment ends on the surface, the surface's own lamp light (direct.h's
//   surface_radiance, the renderers' equation) seen through exp(-c t).
// So a path of k interactions ending at a lamp is counted by the next events of its last
// interaction; the prefix is drawn independently of them. The path goes on by a free flight
// whose density is the channels' mean, (1/3) sum_k c_k exp(-c_k r) (one-sample MIS over the
// channels: every channel's weight stays below 3 b / c), to a scattering in the water (a new
// direction from the phase function) or to the surface (a cosine-weighted direction, weight J).
// Russian roulette on the largest channel's weight ends paths without bias.
//
// The baker (optics/multiple_scattering.h) samples otherwise: free flights with the smallest
// channel's attenuation, no surface, directions from a mixture aimed at the lamps from the
// vertex, no lamp-side technique. Both draw the angle on a segment from PhaseSampler's table.

namespace deepsea {

void validate(const PathTracerOptions& opt, long pixels) {
    if (opt.paths < 1) throw ConfigError("paths: must be at least 1");
    if (opt.min_order < 1) throw ConfigError("min-order: must be at least 1");
    if (opt.max_order < opt.min_order)
        throw ConfigError("max-order: must be at least min-order (" +
                          std::to_string(opt.min_order) + ")");
    if (!(opt.open_water_z >= 0.0)) throw ConfigError("z-max: must be >= 0");
    const double work = double(opt.paths) * double(pixels);
    if (work > kMaxPathWork) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "paths: %ld paths x %ld pixels = %.3g paths, more than the limit of %.3g "
                      "(about a week on two cores): trace fewer paths or a smaller image",
                      opt.paths, pixels, work, kMaxPathWork);
        throw ConfigError(buf);
    }
}

namespace {

enum Layer { kDirect = 0, kForward = 1, kBackscatter = 2 };

/// Where the ray from the current vertex ends.
struct Segment {
    double t_end = std::numeric_limits<double>::infinity();
    bool surface = false;  ///< it ends on the surface
    bool front = false;    ///< on its camera side (the back absorbs)
    Vec3 P, n;             ///< the surface point and its normal
    Rgb albedo;
};

struct Scene {
    const Rig& rig;
    const Water& water;
    const detail::SceneSurface& surface;
    const PhaseSampler& phase;
};

/// Distances s in [0, s_end] on the line O + s d about a point Q (a lamp, or a path vertex
/// seen from a lamp's ray), in the angle theta: s = delta + h tan(theta), h the point's
/// distance from the line. Equiangular sampling (Kulla & Fajardo 2012), theta uniform, makes
/// the density h / ((tb - ta) |O + s d - Q|^2) and cancels the point's inverse square. The
/// light scattered at s between the line and Q turns by psi = pi/2 + theta exactly, so half the
/// samples draw theta in proportion to the phase function instead (PhaseSampler's angle
/// table), for forward-peaked water (one-sample MIS, balance heuristic).
struct Equiangular {
    const PhaseSampler& phase;
    double delta = 0.0, h = 0.0, ta = 0.0, tb = 0.0, mass = 0.0;

    Equiangular(const PhaseSampler& ph, const Vec3& O, const Vec3& d, double s_end, const Vec3& Q)
        : phase(ph) {
        const Vec3 to = Q - O;
        delta = dot(to, d);
        h = std::max(length(to - d * delta), 1e-12);
        ta = std::atan2(-delta, h);
        tb = std::isinf(s_end) ? 0.5 * M_PI : std::atan2(s_end - delta, h);
        if (tb > ta) mass = phase.angle_mass(0.5 * M_PI + ta, 0.5 * M_PI + tb);
    }
    bool empty() const { return !(tb > ta); }
    double sample(double u) const {
        double theta;
        if (!(mass > 0.0)) {
            theta = ta + u * (tb - ta);
        } else if (u < 0.5) {
            theta = ta + 2.0 * u * (tb - ta);
        } else {
            theta =
                phase.sample_angle(0.5 * M_PI + ta, 0.5 * M_PI + tb, 2.0 * u - 1.0) - 0.5 * M_PI;
        }
        return delta + h * std::tan(theta);
    }
    double pdf(double s) const {
        const double theta = std::atan2(s - delta, h);
        const double p_theta =
            mass > 0.0 ? 0.5 / (tb - ta) + 0.5 * phase.angle_density(0.5 * M_PI + theta) / mass
                       : 1.0 / (tb - ta);
        return p_theta * h / (h * h + (s - delta) * (s - delta));
    }
};

/// A path vertex after the camera: where the next direction is chosen.
struct Vertex {
    Vec3 X;
    bool on_surface = false;
    Vec3 from;   ///< volume: the direction of travel that arrived (the phase function's axis)
    Vec3 n;      ///< surface: its normal
    Rgb albedo;  ///< surface
};

/// Density (1/sr) with which the path chooses direction d at v: the phase function's
/// sampling, or cos / pi on the surface's front.
double direction_pdf(const Scene& s, const Vertex& v, const Vec3& d) {
    if (!v.on_surface) return s.phase.pdf(dot(v.from, d));
    return std::max(0.0, dot(v.n, d)) / M_PI;
}

/// What v does to light leaving along d: the phase function p (1/sr; the b is in the path's
/// weight), or the Lambertian J / pi cos.
Rgb vertex_factor(const Scene& s, const Vertex& v, const Vec3& d) {
    if (!v.on_surface) return Rgb(s.water.phase(dot(v.from, d)));
    return v.albedo * (std::max(0.0, dot(v.n, d)) / M_PI);
}

/// Where the ray from X along d meets the surface (infinity if nowhere).
double surface_distance(const Scene& s, const Vec3& X, const Vec3& d, bool leaving_surface) {
    detail::SurfaceHit h;
    return s.surface.hit(X, d, std::numeric_limits<double>::infinity(), h, leaving_surface)
               ? h.t
               : std::numeric_limits<double>::infinity();
}

/// Lamp L's light scattered once at Y toward -d, through exp(-c r) over the r metres before
/// it: the integrand of both next events (volume measure, without the vertex's factor and
/// 1 / r^2). Zero where the surface is in the way.
Rgb scattered_at(const Scene& s, const Light& L, const Vec3& Y, const Vec3& d, double r) {
    if (s.surface.blocks(Y, L.position)) return {};
    return lamp_in_scatter(L, s.water, Y, -d) * transmission(s.water.c, r);
}

/// Density (1/sr) of the lamp-side technique's direction om from lamp L toward vertex X: a
/// third uniform over the sphere, a third the phase function about the direction a from the
/// lamp to X (where a point just in front of the lamp scatters its light toward X), a third
/// uniform in the angle beta to a (density 1 / (2 pi^2 sin beta)), which cancels the glow's
/// 1 / beta.
double lamp_direction_pdf(const Scene& s, const Light& L, const Vec3& X, const Vec3& om) {
    const Vec3 to = X - L.position;
    const double n = length(to);
    double pdf = 1.0 / (4.0 * M_PI);
    if (n > 0.0) {
        const double mu = dot(to / n, om);
        const double sin_beta = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        pdf += s.phase.pdf(mu) + 1.0 / (2.0 * M_PI * M_PI * std::max(sin_beta, 1e-300));
    }
    return pdf / 3.0;
}

/// Density (volume measure, 1/m^3) of the lamp-side technique's choice of Y for vertex X:
/// a direction from the lamp (lamp_direction_pdf), then equiangular about X along it.
double lamp_side_pdf(const Scene& s, const Light& L, const Vec3& X, const Vec3& Y) {
    const Vec3 w = Y - L.position;
    const double rho = length(w);
    if (!(rho > 0.0)) return 0.0;
    const Vec3 om = w / rho;
    const Equiangular e(s.phase, L.position, om, surface_distance(s, L.position, om, false), X);
    return e.empty() ? 0.0 : lamp_direction_pdf(s, L, X, om) * e.pdf(rho) / (rho * rho);
}

/// Density of the path-side technique's choice of Y for vertex v (the path's direction, then
/// equiangular about the lamp along it); `seg_end` is where that direction's segment ends.
double path_side_pdf(const Scene& s, const Light& L, const Vertex& v, const Vec3& d, double r,
                     double seg_end) {
    const Equiangular e(s.phase, v.X, d, seg_end, L.position);
    return e.empty() || r > seg_end ? 0.0 : direction_pdf(s, v, d) * e.pdf(r) / (r * r);
}

/// Lamp L's light scattered once on the segment X + r d, 0 <= r < t_end, toward -d: one
/// equiangular sample. With a vertex (after the camera), weighted against the lamp-side
/// technique by the balance heuristic (Veach 1997).
Rgb segment_light(const Scene& s, const Light& L, const Vertex* v, const Vec3& X, const Vec3& d,
                  double t_end, double u) {
    const Equiangular e(s.phase, X, d, t_end, L.position);
    if (e.empty()) return {};
    const double r = e.sample(u);
    if (!(r >= 0.0) || !(r <= t_end)) return {};  // rounding at the ends
    const Vec3 Y = X + d * r;
    const double pdf = e.pdf(r);
    const Rgb f = scattered_at(s, L, Y, d, r) * (1.0 / pdf);
    if (!v) return f;
    const double pa = direction_pdf(s, *v, d) * pdf / (r * r);
    return f * (pa / (pa + lamp_side_pdf(s, L, X, Y)));
}

/// The lamp-side technique at vertex v: a direction from the lamp (lamp_direction_pdf), then
/// Y equiangular about X along that ray, so that Y's density grows as 1 / |Y - L|^2 at the
/// lamp: a path vertex looking past a point lamp sees its glow grow as 1 / angle (times the
/// phase function's forward peak), which the path's own directions (bounded densities) sample
/// with infinite variance. Balance heuristic against segment_light's technique.
Rgb lamp_side_light(const Scene& s, const Light& L, const Vertex& v, Rng& rng) {
    const double u0 = rng.uniform(), u1 = rng.uniform(), u2 = rng.uniform();
    const Vec3 to_x = v.X - L.position;
    const double len = length(to_x);
    Vec3 om;
    if (u0 < 1.0 / 3.0 || !(len > 0.0)) {
        om = rotate_about(Vec3(0, 0, 1), 1.0 - 2.0 * u1, 2.0 * M_PI * u2);
    } else if (u0 < 2.0 / 3.0) {
        om = s.phase.sample(to_x / len, u1, u2).direction;
    } else {
        om = rotate_about(to_x / len, std::cos(M_PI * u1), 2.0 * M_PI * u2);
    }
    const double u3 = rng.uniform();
    const Equiangular e(s.phase, L.position, om, surface_distance(s, L.position, om, false), v.X);
    if (e.empty()) return {};
    const double rho = e.sample(u3);
    if (!(rho > 0.0)) return {};
    const Vec3 Y = L.position + om * rho;
    const Vec3 to = Y - v.X;
    const double r = length(to);
    if (!(r > 0.0)) return {};
    const Vec3 d = to / r;
    const double seg_end = surface_distance(s, v.X, d, v.on_surface);
    if (r > seg_end) return {};  // the surface is between
    const Rgb f = vertex_factor(s, v, d);
    if (f.max() == 0.0) return {};
    const double pb = lamp_direction_pdf(s, L, v.X, om) * e.pdf(rho) / (rho * rho);
    const double pa = path_side_pdf(s, L, v, d, r, seg_end);
    return f * scattered_at(s, L, Y, d, r) * (1.0 / (r * r * (pa + pb)));
}

/// The surface's lamp light at the end of the segment, seen from its start: L exp(-c t).
/// A point on a plane sees every lamp on its side (surface_radiance's cosine tests that).
Rgb surface_light(const Scene& s, const Segment& seg) {
    const Rgb L = surface_radiance(s.rig, s.water, seg.P, seg.n, seg.albedo);
    const Rgb T = transmission(s.water.c, seg.t_end);
    return {direct_signal(L.r, T.r), direct_signal(L.g, T.g), direct_signal(L.b, T.b)};
}

/// The segment from X along d: to the surface, or unbounded.
Segment next_segment(const Scene& s, const Vec3& X, const Vec3& d, bool leaving_surface) {
    Segment seg;
    detail::SurfaceHit h;
    if (s.surface.hit(X, d, seg.t_end, h, leaving_surface)) {
        seg.t_end = h.t;
        seg.surface = true;
        seg.front = h.front;
        seg.P = h.P;
        seg.n = s.surface.normal();
        seg.albedo = h.albedo;
    }
    return seg;
}

/// One path from the camera along unit direction d whose first segment is `seg`; adds its
/// contributions to out[layer].
void trace(const Scene& s, const PathTracerOptions& opt, Vec3 d, Segment seg, Rng& rng,
           Rgb out[3]) {
    const Rgb& c = s.water.c;
    Rgb w(1.0);    // the path's weight, its last direction's included
    Rgb w_vertex;  // the same before the last vertex's direction (lamp-side next events)
    Vertex v;
    bool touched = false, surface_first = false;
    for (int k = 0;; ++k) {
        // Next events: contributions of order k + 1.
        if (k + 1 >= opt.min_order) {
            const int layer = touched ? (surface_first ? kDirect : kForward) : kBackscatter;
            const Vertex* at = k == 0 ? nullptr : &v;
            for (const Light& L : s.rig.lights) {
                out[layer] += w * segment_light(s, L, at, v.X, d, seg.t_end, rng.uniform());
                if (!at) continue;
                out[layer] += w_vertex * lamp_side_light(s, L, v, rng);
            }
            if (seg.surface && seg.front)
                out[k == 0 || surface_first ? kDirect : kForward] += w * surface_light(s, seg);
        }
        if (k + 1 >= opt.max_order) return;
        // Free flight, density (1/3) sum_k c_k exp(-c_k r): a channel, then its exponential.
        const int ch = std::min(int(3.0 * rng.uniform()), 2);
        const double u = rng.uniform();
        const double r = c[ch] > 0.0 ? -std::log1p(-u) / c[ch] : seg.t_end;
        if (r < seg.t_end) {
            double pdf = 0.0;
            for (int j = 0; j < 3; ++j) pdf += c[j] * transmission(c[j], r) / 3.0;
            if (!(pdf > 0.0)) return;
            w_vertex = w * s.water.b * transmission(c, r) * (1.0 / pdf);
            v = Vertex{v.X + d * r, false, d, {}, {}};
            const PhaseSample ps = s.phase.sample(d, rng.uniform(), rng.uniform());
            d = ps.direction;
            w = w_vertex * ps.weight;
        } else if (seg.surface && seg.front) {
            double reach = 0.0;  // probability that the flight reaches the surface
            for (int j = 0; j < 3; ++j) reach += transmission(c[j], seg.t_end) / 3.0;
            if (!(reach > 0.0)) return;
            w_vertex = w * transmission(c, seg.t_end) * (1.0 / reach);
            v = Vertex{s.surface.project(seg.P), true, d, seg.n, seg.albedo};
            const double u1 = rng.uniform(), u2 = rng.uniform();
            d = rotate_about(seg.n, std::sqrt(u1), 2.0 * M_PI * u2);  // pdf cos / pi
            w = w_vertex * seg.albedo;
            if (k == 0) surface_first = true;
            touched = true;
        } else {
            return;  // escaped, or absorbed by the surface's back
        }
        // Russian roulette: survive with the largest channel's weight, when below 1.
        const double m = w.max();
        if (m < 1.0) {
            if (rng.uniform() >= m) return;
            w = w * (1.0 / m);
            w_vertex = w_vertex * (1.0 / m);
        }
        seg = next_segment(s, v.X, d, v.on_surface);
    }
}

void put(Image& img, int u, int v, const Rgb& x) {
    float* p = &img.at(u, v);
    p[0] = float(x.r);
    p[1] = float(x.g);
    p[2] = float(x.b);
}

/// Sums of one layer's per-path values and of their squares.
struct Moments {
    Rgb s1, s2;
    void add(const Rgb& x) {
        s1 += x;
        s2 += x * x;
    }
    Rgb mean(double n) const { return s1 / n; }
    Rgb std_error(double n) const {
        if (n < 2.0) return {};
        Rgb se;
        for (int ch = 0; ch < 3; ++ch) {
            const double m = s1[ch] / n;
            se[ch] = std::sqrt(std::max(0.0, (s2[ch] - n * m * m) / (n - 1.0)) / n);
        }
        return se;
    }
};

}  // namespace

PathTraced render_path_traced(const Camera& cam, const Rig& rig, const Water& water,
                              const Image& rgb, const Image& zdepth, const PathTracerOptions& opt,
                              const Parallel& par) {
    if (rgb.channels != 3) throw InputError("colour image must have 3 channels");
    if (zdepth.channels != 1) throw InputError("depth image must have 1 channel");
    require_same_size(rgb, zdepth, "colour and depth images");
    if (rgb.width != cam.width || rgb.height != cam.height)
        throw InputError("images are " + std::to_string(rgb.width) + "x" +
                         std::to_string(rgb.height) + " but the camera is " + describe(cam));
    const long pixels = long(cam.width) * cam.height;
    validate(opt, pixels);
    const detail::SceneSurface surface(cam, rgb, zdepth);
    const PhaseSampler phase(water.phase);
    const Scene scene{rig, water, surface, phase};
    ReferenceOptions ro;
    ro.open_water_z = opt.open_water_z;
    const double z_open = open_water_depth(water, ro);

    PathTraced out;
    out.layers.resize(cam.width, cam.height);
    out.std_error.resize(cam.width, cam.height);
    const double n = double(opt.paths);
    parallel_for(
        std::size_t(pixels),
        [&](std::size_t begin, std::size_t end) {
            for (std::size_t p = begin; p < end; ++p) {
                const int u = int(p % std::size_t(cam.width)), v = int(p / cam.width);
                const double z = zdepth.at(u, v);
                const float* a = rgb.data.data() + rgb.index(u, v);
                const Rgb J(a[0], a[1], a[2]);
                Segment centre;  // the pixel's own surface point, exactly
                const Vec3 rc = cam.ray(u, v);
                if (has_surface(z)) {
                    centre.surface = centre.front = true;
                    centre.P = rc * z;
                    centre.t_end = length(centre.P);
                    centre.n = surface_normal(cam, zdepth, u, v);
                    centre.albedo = J;
                    put(out.layers.transmission, u, v, transmission(water.c, centre.t_end));
                    put(out.layers.normal, u, v, {centre.n.x, centre.n.y, centre.n.z});
                    out.layers.depth.at(u, v) = float(z);
                } else {
                    centre.t_end = z_open * length(rc);
                }
                Moments m[4];  // direct, forward, backscatter, final
                for (long i = 0; i < opt.paths; ++i) {
                    throw_if_stopped(par.stop);
                    Rng rng(mix_seed(opt.seed, p, std::uint64_t(i)));
                    Vec3 d = normalize(rc);
                    Segment seg = centre;
                    if (opt.box_filter) {
                        const double du = rng.uniform() - 0.5, dv = rng.uniform() - 0.5;
                        const Vec3 r = cam.ray(u + du, v + dv);
                        d = normalize(r);
                        seg = next_segment(scene, Vec3(), d, false);
                        if (!seg.surface) seg.t_end = z_open * length(r);
                    }
                    Rgb c[3];
                    trace(scene, opt, d, seg, rng, c);
                    for (int l = 0; l < 3; ++l) m[l].add(c[l]);
                    m[3].add(c[0] + c[1] + c[2]);
                }
                Image* est[4] = {&out.layers.direct, &out.layers.forward, &out.layers.backscatter,
                                 &out.layers.final};
                Image* se[4] = {&out.std_error.direct, &out.std_error.forward,
                                &out.std_error.backscatter, &out.std_error.final};
                for (int l = 0; l < 4; ++l) {
                    put(*est[l], u, v, m[l].mean(n));
                    put(*se[l], u, v, m[l].std_error(n));
                }
            }
        },
        par.or_grain(1));
    return out;
}

}  // namespace deepsea
