#include "deepsea/camera/distortion.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

/// distort() at (x, y) and its Jacobian (a b; c d).
void distort_jacobian(const Distortion& k, double x, double y, double& xd, double& yd, double& a,
                      double& b, double& c, double& d) {
    distort(k, x, y, xd, yd);
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (k.k1 + r2 * (k.k2 + r2 * k.k3));
    const double dradial = k.k1 + r2 * (2.0 * k.k2 + 3.0 * r2 * k.k3);  // d radial / d r^2
    a = radial + 2.0 * x * x * dradial + 2.0 * k.p1 * y + 6.0 * k.p2 * x;
    b = 2.0 * x * y * dradial + 2.0 * k.p1 * x + 2.0 * k.p2 * y;
    c = b;
    d = radial + 2.0 * y * y * dradial + 6.0 * k.p1 * y + 2.0 * k.p2 * x;
}

std::string fmt3(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

[[noreturn]] void fold(const std::string& why) {
    throw SchemaError("camera.lens.distortion",
                      "folds the image over: " + why + "; weaken the distortion coefficients");
}

}  // namespace

bool undistort(const Distortion& k, double xd, double yd, double& x, double& y) {
    x = xd;
    y = yd;
    double fx, fy, a, b, c, d;
    distort_jacobian(k, x, y, fx, fy, a, b, c, d);
    double err = std::hypot(fx - xd, fy - yd);
    for (int it = 0; it < 50 && err > 1e-12; ++it) {
        const double det = a * d - b * c;
        if (!(std::fabs(det) > 1e-300)) return false;
        const double ex = fx - xd, ey = fy - yd;
        const double sx = (d * ex - b * ey) / det, sy = (a * ey - c * ex) / det;
        // Damped: halve the step until the residual falls (Newton overshoots near a fold).
        double t = 1.0;
        for (int half = 0; half < 30; ++half, t *= 0.5) {
            const double nx = x - t * sx, ny = y - t * sy;
            double gx, gy, na, nb, nc, nd;
            distort_jacobian(k, nx, ny, gx, gy, na, nb, nc, nd);
            const double nerr = std::hypot(gx - xd, gy - yd);
            if (nerr < err) {
                x = nx, y = ny, fx = gx, fy = gy, a = na, b = nb, c = nc, d = nd, err = nerr;
                break;
            }
        }
        if (t < 1e-8) return false;
    }
    return err <= 1e-10 * std::max(1.0, std::hypot(xd, yd)) && std::isfinite(x) && std::isfinite(y);
}

void check_distortion(const Distortion& k, const Camera& cam) {
    if (!k.enabled()) return;
    // The image's field: its farthest outer pixel edge corner, as a distorted radius.
    double reach = 0.0;
    for (double u : {-0.5, cam.width - 0.5})
        for (double v : {-0.5, cam.height - 0.5})
            reach = std::max(reach, std::hypot(cam.ray_x(u), cam.ray_y(v)));
    const auto g = [&](double s) {  // distorted radius at r^2 = s
        return std::sqrt(s) * (1.0 + s * (k.k1 + s * (k.k2 + s * k.k3)));
    };
    const auto slope = [&](double s) {  // d g / d r at r^2 = s
        return 1.0 + s * (3.0 * k.k1 + s * (5.0 * k.k2 + s * 7.0 * k.k3));
    };
    const auto deg = [](double r) { return fmt3(std::atan(r) * 180.0 / M_PI); };
    const std::string field = "the image's field, which reaches r = " + fmt3(reach) + " (" +
                              deg(reach) + " degrees from the axis) at its corners";
    // Walk out in r until the distorted radius reaches the corners, the slope staying > 0.
    const double step = reach / 4000.0, limit = 20.0 * reach + 10.0;
    double r = 0.0;
    while (g(r * r) < reach) {
        if (!(slope(r * r) > 0.0)) {
            double lo = r - step;  // the slope's zero, to 1e-12, for the message
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + r);
                (slope(mid * mid) > 0.0 ? lo : r) = mid;
            }
            fold("the radial mapping r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing at r = " +
                 fmt3(r) + " (" + deg(r) + " degrees), inside " + field);
        }
        r += step;
        if (r > limit)
            fold("the radial mapping r (1 + k1 r^2 + k2 r^4 + k3 r^6) never reaches " + field);
    }
    // The slope is a cubic in s = r^2: between the samples its minimum lies at a root of
    // 3 k1 + 10 k2 s + 21 k3 s^2.
    const double A = 21.0 * k.k3, B = 10.0 * k.k2, C = 3.0 * k.k1;
    std::vector<double> critical;
    if (A != 0.0) {
        const double disc = B * B - 4.0 * A * C;
        if (disc >= 0.0) {
            critical.push_back((-B + std::sqrt(disc)) / (2.0 * A));
            critical.push_back((-B - std::sqrt(disc)) / (2.0 * A));
        }
    } else if (B != 0.0) {
        critical.push_back(-C / B);
    }
    for (double s : critical)
        if (s > 0.0 && s < r * r && !(slope(s) > 0.0))
            fold("the radial mapping r (1 + k1 r^2 + k2 r^4 + k3 r^6) stops increasing at r = " +
                 fmt3(std::sqrt(s)) + " (" + deg(std::sqrt(s)) + " degrees), inside " + field);
}

namespace {

/// True where recorded pixel (u, v) has a ray that lands on it with the image not folded there
/// (the Jacobian's determinant > 0); its ray in x, y.
bool ray_of(const Distortion& d, const Camera& cam, int u, int v, double& x, double& y) {
    if (!undistort(d, cam.ray_x(u), cam.ray_y(v), x, y)) return false;
    double xd, yd, a, b, c, e;
    distort_jacobian(d, x, y, xd, yd, a, b, c, e);
    return a * e - b * c > 0.0;
}

[[noreturn]] void no_ray(int u, int v) {
    fold("no ray lands on pixel (" + std::to_string(u) + ", " + std::to_string(v) +
         ") without the image folding there (the tangential terms p1, p2 or the radial ones)");
}

}  // namespace

DistortionMap::DistortionMap(const Camera& cam, const Distortion& d) : m_camera(cam), m_d(d) {
    if (!d.enabled()) return;
    check_distortion(d, cam);
    const int w = cam.width, h = cam.height;
    // A coarse grid first, in order: a fold (always many pixels wide) is named quickly, by
    // the same pixel every time.
    const auto next = [](int i, int n) { return i == n - 1 ? n : std::min(i + 16, n - 1); };
    double x, y;
    for (int v = 0; v < h; v = next(v, h))
        for (int u = 0; u < w; u = next(u, w))
            if (!ray_of(d, cam, u, v, x, y)) no_ray(u, v);
    m_taps.resize(std::size_t(w) * h);
    std::atomic<long> outside{0};
    std::atomic<long> failed{-1};  // the first pixel with no ray (row-major), if any
    parallel_for(
        std::size_t(h),
        [&](std::size_t v0, std::size_t v1) {
            long out = 0;
            for (int v = int(v0); v < int(v1); ++v) {
                for (int u = 0; u < w; ++u) {
                    double x, y;
                    if (!ray_of(d, cam, u, v, x, y)) {
                        long expect = failed.load();
                        const long here = long(v) * w + u;
                        while ((expect < 0 || here < expect) &&
                               !failed.compare_exchange_weak(expect, here)) {
                        }
                        continue;
                    }
                    double su = cam.fx * x + cam.cx, sv = cam.fy * y + cam.cy;
                    if (su < -0.5 || su > w - 0.5 || sv < -0.5 || sv > h - 0.5) ++out;
                    su = std::clamp(su, 0.0, double(w - 1));
                    sv = std::clamp(sv, 0.0, double(h - 1));
                    const int x0 = w > 1 ? std::min(int(su), w - 2) : 0;
                    const int y0 = h > 1 ? std::min(int(sv), h - 2) : 0;
                    m_taps[std::size_t(v) * w + u] = {std::uint32_t(std::size_t(y0) * w + x0),
                                                      float(su - x0), float(sv - y0)};
                }
            }
            outside += out;
        },
        Parallel().or_grain(8));
    if (failed >= 0) no_ray(int(failed % w), int(failed / w));
    m_outside = double(outside) / double(m_taps.size());
}

void DistortionMap::source(int u, int v, double& su, double& sv) const {
    double x, y;
    undistort(m_d, m_camera.ray_x(u), m_camera.ray_y(v), x, y);
    su = m_camera.fx * x + m_camera.cx;
    sv = m_camera.fy * y + m_camera.cy;
}

void DistortionMap::resample_row(const Image& src, int v, float* dst) const {
    const int w = m_camera.width;
    const std::size_t ox = w > 1 ? 3 : 0, oy = m_camera.height > 1 ? 3 * std::size_t(w) : 0;
    const Tap* taps = m_taps.data() + std::size_t(v) * w;
    const float* s = src.data.data();
    for (int u = 0; u < w; ++u) {
        const Tap t = taps[u];
        const float* p = s + 3 * std::size_t(t.index);
        for (int c = 0; c < 3; ++c) {
            const float a = p[c], b = p[c + ox], cc = p[c + oy], d = p[c + ox + oy];
            const float top = a + t.wx * (b - a), bottom = cc + t.wx * (d - cc);
            dst[3 * u + c] = top + t.wy * (bottom - top);
        }
    }
}

void DistortionMap::resample(const Image& src, Image& dst, const Parallel& par) const {
    require_same_size(src.width, src.height, m_camera.width, m_camera.height,
                      "distortion: the rendered image");
    if (dst.width != src.width || dst.height != src.height || dst.channels != 3)
        dst = Image(src.width, src.height, 3);
    if (empty()) {
        dst.data = src.data;
        return;
    }
    parallel_for(
        std::size_t(src.height),
        [&](std::size_t v0, std::size_t v1) {
            for (std::size_t v = v0; v < v1; ++v) resample_row(src, int(v), dst.row(int(v)));
        },
        par.or_grain(16));
}

}  // namespace deepsea
