#include "scene_surface.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/optics/normals.h"

namespace deepsea::detail {

namespace {

/// A surface pixel may lie this far off the plane, relative to its depth: float depth maps
/// hold 6e-8, and the averaged normal's error times the image's lateral extent stays well below.
constexpr double kPlaneTolerance = 1e-4;

double median(std::vector<double>& x) {
    const auto mid = x.begin() + std::ptrdiff_t(x.size() / 2);
    std::nth_element(x.begin(), mid, x.end());
    return *mid;
}

std::string pixel(int u, int v) {
    return "pixel (" + std::to_string(u) + ", " + std::to_string(v) + ")";
}

}  // namespace

SceneSurface::SceneSurface(const Camera& cam, const Image& rgb, const Image& zdepth)
    : m_cam(cam), m_rgb(rgb) {
    // The plane: the median of the pixels' own normals (component-wise), through the median of
    // their offsets, so that a pixel off the plane is named, not the plane tilted towards it.
    std::vector<double> nx, ny, nz;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            if (!has_surface(double(zdepth.at(u, v)))) continue;
            const Vec3 n = surface_normal(cam, zdepth, u, v);
            nx.push_back(n.x);
            ny.push_back(n.y);
            nz.push_back(n.z);
        }
    }
    if (nx.empty()) return;
    const Vec3 n(median(nx), median(ny), median(nz));
    if (!(length(n) > 0.0)) throw InputError("the depth map's surface normals cancel out");
    m_n = normalize(n);
    std::vector<double> offsets;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const double z = zdepth.at(u, v);
            if (has_surface(z)) offsets.push_back(dot(m_n, cam.ray(u, v) * z));
        }
    }
    m_offset = median(offsets);
    m_plane = true;
    for (int v = 0; v < cam.height; ++v) {
        for (int u = 0; u < cam.width; ++u) {
            const double z = zdepth.at(u, v);
            const Vec3 r = cam.ray(u, v);
            if (has_surface(z)) {
                const double off = dot(m_n, r * z) - m_offset;
                if (std::fabs(off) > kPlaneTolerance * z) {
                    char buf[160];
                    std::snprintf(buf, sizeof buf,
                                  " lies %.3g m off the plane of the others: the "
                                  "multiple-scattering reference takes open water or one plane",
                                  off);
                    throw InputError(pixel(u, v) + buf);
                }
            } else {
                const double nr = dot(m_n, r);
                const double zp = nr < 0.0 ? m_offset / nr : -1.0;
                if (zp > 0.0 && zp < kFarDepth) {
                    throw InputError(pixel(u, v) +
                                     " is open water, but the plane of the surface "
                                     "pixels crosses its ray at z = " +
                                     std::to_string(zp) + " m");
                }
            }
        }
    }
}

Rgb SceneSurface::albedo_at(const Vec3& P) const {
    // The pixel the point projects to, the border's beyond the frame.
    const double u = m_cam.cx + m_cam.fx * P.x / P.z, v = m_cam.cy + m_cam.fy * P.y / P.z;
    const int iu = int(std::lround(std::clamp(u, 0.0, double(m_cam.width - 1))));
    const int iv = int(std::lround(std::clamp(v, 0.0, double(m_cam.height - 1))));
    const float* p = m_rgb.data.data() + m_rgb.index(iu, iv);
    return {p[0], p[1], p[2]};
}

Vec3 SceneSurface::project(const Vec3& O) const {
    return m_plane ? O - m_n * (dot(m_n, O) - m_offset) : O;
}

bool SceneSurface::hit(const Vec3& O, const Vec3& d, double t_max, SurfaceHit& out,
                       bool leaving) const {
    if (!m_plane || leaving) return false;
    const double nd = dot(m_n, d);
    if (nd == 0.0) return false;
    const double t = (m_offset - dot(m_n, O)) / nd;
    if (!(t > 0.0) || !(t < t_max)) return false;
    const Vec3 P = O + d * t;
    if (!(P.z > 0.0)) return false;
    out.t = t;
    out.P = P;
    out.front = nd < 0.0;
    out.albedo = out.front ? albedo_at(P) : Rgb();
    return true;
}

bool SceneSurface::blocks(const Vec3& A, const Vec3& B) const {
    if (!m_plane) return false;
    const double sa = dot(m_n, A) - m_offset, sb = dot(m_n, B) - m_offset;
    const double eps = 1e-12 * (1.0 + length(A) + length(B));
    if (std::fabs(sa) <= eps || std::fabs(sb) <= eps || (sa > 0.0) == (sb > 0.0)) return false;
    const Vec3 X = A + (B - A) * (sa / (sa - sb));
    return X.z > 0.0;
}

}  // namespace deepsea::detail
