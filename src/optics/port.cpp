#include "deepsea/optics/port.h"

#include <algorithm>
#include <cstdio>

#include "deepsea/core/error.h"
#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

const char* const kChannel[] = {"R", "G", "B"};

/// Distance along unit d from p, inside the sphere |x - c| = r, to where it leaves the sphere:
/// the positive root of s^2 + 2 b s - h = 0 (b = (p - c) . d, h = r^2 - |p - c|^2 > 0), in
/// the form without cancellation. NaN when p is not inside.
double exit_distance(const Vec3& p, const Vec3& d, const Vec3& c, double r) {
    const Vec3 q = p - c;
    const double b = dot(q, d), h = r * r - dot(q, q);
    if (!(h > 0.0)) return std::nan("");
    const double root = std::sqrt(b * b + h);
    return b <= 0.0 ? root - b : h / (root + b);
}

/// Four significant digits, for derived values in messages (89.99, not 89.9999641901378).
std::string digits4(double x) {
    char s[32];
    std::snprintf(s, sizeof s, "%.4g", x);
    return s;
}

std::string deg(double cos_angle) {
    return digits4(std::acos(std::min(1.0, cos_angle)) * 180.0 / M_PI);
}

/// "total internal reflection at the <surface> for <ray>, 58.7 degrees from the surface's normal
/// on the incident side: n1 sin = 1.14 > n2 = 1; part of the image sees no water".
std::string total_reflection(const char* surface, const std::string& ray, double cos_incident,
                             const char* n1, double n1_sin, const char* n2,
                             const std::string& n2_value) {
    return std::string("total internal reflection at the ") + surface + " for " + ray + ", " +
           deg(cos_incident) + " degrees from the surface's normal on the incident side: " + n1 +
           " sin = " + digits4(n1_sin) + " > " + n2 + " = " + n2_value +
           "; part of the image sees no water";
}

std::string triple(const Vec3& v) {
    return "[" + short_number(v.x) + ", " + short_number(v.y) + ", " + short_number(v.z) + "]";
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void require_length(double x, const std::string& key, bool zero_allowed) {
    if (zero_allowed ? !(x >= 0.0) : !(x > 0.0))
        throw SchemaError(key, std::string(zero_allowed ? "must be >= 0" : "must be > 0") +
                                   ", got " + short_number(x));
    if (!(x <= kMaxPortLength))
        throw SchemaError(
            key, "must be at most " + short_number(kMaxPortLength) + " m, got " + short_number(x));
}

void require_index(double n, const std::string& key) {
    if (!(n > 0.0) || !std::isfinite(n))
        throw SchemaError(key, "must be > 0 and finite, got " + short_number(n));
}

}  // namespace

PortRay trace_port(const Port& port, const Vec3& air) {
    PortRay r;
    const Vec3 d = normalize(air);
    r.air = d;
    // The inner surface: where the ray meets it and its unit normal there.
    Vec3 n_in;
    if (port.kind == PortKind::Flat) {
        n_in = normalize(port.flat.normal);
        const double c = dot(d, n_in);
        if (!(c > 0.0)) {
            r.status = PortRayStatus::Behind;
            return r;
        }
        r.inner = d * (port.flat.distance / c);
    } else {
        const double s = exit_distance({}, d, port.dome.centre, port.dome.radius);
        if (!std::isfinite(s)) {  // the camera is not inside the dome
            r.status = PortRayStatus::Behind;
            return r;
        }
        r.inner = d * s;
        n_in = normalize(r.inner - port.dome.centre);
    }
    r.cos_air = std::fabs(dot(d, n_in));
    Vec3T<double> g{};
    if (!refract(vec3t(d), vec3t(n_in), port.n_air, port.n_glass, g)) {
        r.status = PortRayStatus::InnerReflection;
        return r;
    }
    r.glass = vec3(g);
    r.cos_glass_inner = std::fabs(dot(r.glass, n_in));
    // The outer surface: the origin of the water-side ray.
    Vec3 n_out;
    if (port.kind == PortKind::Flat) {
        n_out = n_in;
        r.origin = r.inner + r.glass * (port.flat.glass_thickness / dot(r.glass, n_out));
    } else {
        const double R = port.dome.radius + port.dome.glass_thickness;
        r.origin = r.inner + r.glass * exit_distance(r.inner, r.glass, port.dome.centre, R);
        n_out = normalize(r.origin - port.dome.centre);
    }
    r.cos_glass_outer = std::fabs(dot(r.glass, n_out));
    for (int c = 0; c < 3; ++c) {
        if (c > 0 && port.n_water[c] == port.n_water[c - 1]) {
            r.direction[c] = r.direction[c - 1];
            r.cos_water[c] = r.cos_water[c - 1];
            continue;
        }
        Vec3T<double> w{};
        if (!refract(g, vec3t(n_out), port.n_glass, port.n_water[c], w)) {
            r.status = PortRayStatus::OuterReflection;
            return r;
        }
        r.direction[c] = vec3(w);
        r.cos_water[c] = std::fabs(dot(r.direction[c], n_out));
    }
    return r;
}

PortRay trace_port(const Port& port, const Camera& camera, double u, double v) {
    return trace_port(port, camera.ray(u, v));
}

Rgb port_radiance_factor(const Port& port, const PortRay& ray) {
    if (!ray.valid()) return Rgb(0.0);
    Rgb f;
    const auto t1 =
        fresnel_transmittance(port.n_air, port.n_glass, ray.cos_air, ray.cos_glass_inner);
    for (int c = 0; c < 3; ++c) {
        const double k = port.n_air / port.n_water[c];
        f[c] = k * k;
        if (!port.fresnel) continue;
        const auto t2 = fresnel_transmittance(port.n_glass, port.n_water[c], ray.cos_glass_outer,
                                              ray.cos_water[c]);
        f[c] *= 0.5 * (t1.s * t2.s + t1.p * t2.p);
    }
    return f;
}

double port_water_fx(const Port& port, const Camera& camera) {
    const PortRay a = trace_port(port, camera, camera.cx - 0.5, camera.cy);
    const PortRay b = trace_port(port, camera, camera.cx + 0.5, camera.cy);
    const auto angle = [](const Vec3& x, const Vec3& y) { return length(cross(x, y)); };
    const double water = a.valid() && b.valid() ? angle(a.direction[1], b.direction[1]) : 0.0;
    return water > 0.0 ? camera.fx * angle(a.air, b.air) / water : camera.fx;
}

void validate(const Port& port) {
    const std::string key = std::string("camera.port.") + port.name() + ".";
    if (port.kind == PortKind::Flat) {
        const FlatPort& f = port.flat;
        if (!finite(f.normal) || !(length(f.normal) > 1e-12) || !std::isfinite(length(f.normal)))
            throw SchemaError(key + "normal", "must be a non-zero vector of finite length, got " +
                                                  triple(f.normal));
        require_length(f.distance, key + "distance", true);
        require_length(f.glass_thickness, key + "glass_thickness", false);
    } else {
        const DomePort& d = port.dome;
        if (!finite(d.centre)) throw SchemaError(key + "centre", "coordinates must be finite");
        require_length(d.radius, key + "radius", false);
        if (!(length(d.centre) < d.radius))
            throw SchemaError(key + "centre",
                              "puts the camera centre outside the dome: |centre| = " +
                                  short_number(length(d.centre)) +
                                  " m >= radius = " + short_number(d.radius) +
                                  " m (the inner surface's radius); the camera must be inside");
        require_length(d.glass_thickness, key + "glass_thickness", false);
    }
    require_index(port.n_air, key + "n_air");
    require_index(port.n_glass, key + "n_glass");
    for (int c = 0; c < 3; ++c)
        if (!(port.n_water[c] > 0.0) || !std::isfinite(port.n_water[c]))
            throw SchemaError(key + "n_water", std::string("must be > 0 and finite (") +
                                                   kChannel[c] + " is " +
                                                   short_number(port.n_water[c]) + ")");
}

void check_port_view(const Port& port, const Camera& camera) {
    const std::string key = std::string("camera.port.") + port.name() + ".";
    const auto check = [&](double u, double v) {
        const PortRay r = trace_port(port, camera, u, v);
        if (r.valid()) return;
        const std::string ray = "the ray through image point (u, v) = (" + short_number(u) + ", " +
                                short_number(v) + ")";
        switch (r.status) {
            case PortRayStatus::Ok:
                return;
            case PortRayStatus::Behind:
                if (port.kind == PortKind::Dome)
                    throw SchemaError(key + "centre", "the camera is not inside the dome");
                throw SchemaError(key + "normal",
                                  "the interface is behind the camera for " + ray +
                                      ": it meets the plane n . x = distance (normal " +
                                      triple(port.flat.normal) +
                                      ") only behind the camera centre or never; the normal "
                                      "points from the camera into the water");
            case PortRayStatus::InnerReflection: {
                const double sin = std::sqrt(std::max(0.0, 1.0 - r.cos_air * r.cos_air));
                throw SchemaError(
                    key + "n_glass",
                    total_reflection("inner surface (air to glass)", ray, r.cos_air, "n_air",
                                     port.n_air * sin, "n_glass", short_number(port.n_glass)));
            }
            case PortRayStatus::OuterReflection: {
                const double cos = r.cos_glass_outer;
                const double sin = std::sqrt(std::max(0.0, 1.0 - cos * cos));
                int c = 0;  // the first channel that reflects
                while (c < 2 && port.n_water[c] >= port.n_glass * sin) ++c;
                throw SchemaError(
                    key + "n_water",
                    total_reflection("outer surface (glass to water)", ray, cos, "n_glass",
                                     port.n_glass * sin, "n_water",
                                     short_number(port.n_water[c]) + " (" + kChannel[c] + ")"));
            }
        }
    };
    const double right = camera.width - 0.5, bottom = camera.height - 0.5;
    check(0.5 * (camera.width - 1), 0.5 * (camera.height - 1));
    for (int i = 0; i <= camera.width; ++i) {
        check(i - 0.5, -0.5);
        check(i - 0.5, bottom);
    }
    for (int j = 0; j <= camera.height; ++j) {
        check(-0.5, j - 0.5);
        check(right, j - 0.5);
    }
}

bool same_rays(const Port& a, const Port& b) {
    const auto same = [](const Vec3& x, const Vec3& y) {
        return x.x == y.x && x.y == y.y && x.z == y.z;
    };
    if (a.kind != b.kind || a.n_air != b.n_air || a.n_glass != b.n_glass ||
        a.n_water.r != b.n_water.r || a.n_water.g != b.n_water.g || a.n_water.b != b.n_water.b)
        return false;
    if (a.kind == PortKind::Flat)
        return same(a.flat.normal, b.flat.normal) && a.flat.distance == b.flat.distance &&
               a.flat.glass_thickness == b.flat.glass_thickness;
    return same(a.dome.centre, b.dome.centre) && a.dome.radius == b.dome.radius &&
           a.dome.glass_thickness == b.dome.glass_thickness;
}

std::string describe(const Port& p) {
    std::string s = std::string(p.name()) + " port (";
    if (p.kind == PortKind::Flat)
        s += "normal " + triple(p.flat.normal) + ", distance " + short_number(p.flat.distance) +
             " m, glass " + short_number(p.flat.glass_thickness) + " m";
    else
        s += "centre " + triple(p.dome.centre) + " m, radius " + short_number(p.dome.radius) +
             " m, glass " + short_number(p.dome.glass_thickness) + " m";
    s += ", n_air " + short_number(p.n_air) + ", n_glass " + short_number(p.n_glass) + ", n_water ";
    s += p.dispersive() ? "[" + short_number(p.n_water.r) + ", " + short_number(p.n_water.g) +
                              ", " + short_number(p.n_water.b) + "]"
                        : short_number(p.n_water.g);
    return s + (p.fresnel ? ", fresnel)" : ")");
}

std::vector<double> colmap_params(const Port& port) {
    const double nw = port.n_water.g;
    if (port.kind == PortKind::Flat) {
        const Vec3 n = normalize(port.flat.normal);
        return {n.x,        n.y,          n.z, port.flat.distance, port.flat.glass_thickness,
                port.n_air, port.n_glass, nw};
    }
    const DomePort& d = port.dome;
    return {d.centre.x,        d.centre.y, d.centre.z,   d.radius,
            d.glass_thickness, port.n_air, port.n_glass, nw};
}

Port port_from_colmap(const std::string& model, const std::vector<double>& p) {
    Port port;
    if (model == "FLATPORT")
        port.kind = PortKind::Flat;
    else if (model == "DOMEPORT")
        port.kind = PortKind::Dome;
    else
        throw ConfigError("Refractive COLMAP port model '" + model +
                          "': expected FLATPORT or DOMEPORT");
    if (p.size() != 8)
        throw ConfigError(model + " takes 8 parameters (" +
                          (port.kind == PortKind::Flat
                               ? "Nx, Ny, Nz, int_dist, int_thick, na, ng, nw"
                               : "Cx, Cy, Cz, int_radius, int_thick, na, ng, nw") +
                          "), got " + std::to_string(p.size()));
    if (port.kind == PortKind::Flat)
        port.flat = {{p[0], p[1], p[2]}, p[3], p[4]};
    else
        port.dome = {{p[0], p[1], p[2]}, p[3], p[4]};
    port.n_air = p[5];
    port.n_glass = p[6];
    port.n_water = Rgb(p[7]);
    return port;
}

}  // namespace deepsea
