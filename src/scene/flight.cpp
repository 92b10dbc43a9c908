// The demo flight: a camera path over the procedural seafloor, rendered to RGB-D frames.
// docs/scene.md describes it.

#include "deepsea/scene/flight.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "deepsea/core/error.h"
#include "deepsea/scene/seafloor.h"

namespace deepsea {

FlightPose flight_pose(const FlightParams& flight, int index) {
    const double p = flight.pitch_deg * (3.14159265358979323846 / 180.0);
    const double s = std::sin(p), c = std::cos(p);
    FlightPose pose;
    pose.origin = {double(index) * flight.speed, 0.0, flight.altitude};
    pose.forward = {s, 0.0, -c};
    pose.down = {-c, 0.0, -s};
    pose.right = {0.0, -1.0, 0.0};
    return pose;
}

namespace {

constexpr double kMinClearance = 0.05;  // m between the camera and the floor below it

void validate(const FlightParams& f, int index) {
    const Camera& cam = f.camera;
    auto bad = [](const std::string& what) { throw ConfigError("scene: " + what); };
    if (cam.width <= 0 || cam.height <= 0) {
        bad("image size must be positive, got " + std::to_string(cam.width) + "x" +
            std::to_string(cam.height));
    }
    if (cam.width > kMaxFlightSide || cam.height > kMaxFlightSide ||
        (long long)cam.width * cam.height > kMaxFlightPixels) {
        bad("image size " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
            " is larger than the scene's limit of " + std::to_string(kMaxFlightPixels >> 20) +
            " megapixels (at most " + std::to_string(kMaxFlightSide) + " on a side)");
    }
    if (!(cam.fx > 0.0) || !(cam.fy > 0.0) || !std::isfinite(cam.fx) || !std::isfinite(cam.fy)) {
        bad("focal lengths fx, fy must be positive");
    }
    if (!std::isfinite(cam.cx) || !std::isfinite(cam.cy)) bad("cx, cy must be finite");
    if (!(f.altitude > 0.0) || !std::isfinite(f.altitude)) bad("altitude must be > 0 m");
    if (!std::isfinite(f.speed)) bad("speed must be finite");
    if (!(std::fabs(f.pitch_deg) < 90.0)) bad("pitch must be within (-90, 90) degrees");
    if (!(f.relief >= 0.0) || !std::isfinite(f.relief)) bad("relief must be >= 0");
    if (!(f.max_range > 0.0 && f.max_range <= kMaxFlightRange))
        bad("max range must be in (0, " + std::to_string(int(kMaxFlightRange)) + "] m");
    if (index < 0) bad("frame index must be >= 0");
}

/// Throws unless the camera of frame `index` is at least kMinClearance above the floor.
void check_clearance(const FlightParams& f, const Seafloor& floor, int index) {
    const FlightPose pose = flight_pose(f, index);
    const double ground = floor.height(pose.origin.x, pose.origin.y);
    if (pose.origin.z - ground < kMinClearance) {
        char msg[256];
        std::snprintf(msg, sizeof msg,
                      "scene: altitude %g m puts the camera of frame %d within 5 cm of the "
                      "seafloor (%.3f m high there); raise the altitude or lower the relief",
                      f.altitude, index, ground);
        throw ConfigError(msg);
    }
}

}  // namespace

void validate_flight(const FlightParams& flight) {
    if (flight.frames < 1 || flight.frames > kMaxFlightFrames) {
        throw ConfigError("scene: frames must be from 1 to " + std::to_string(kMaxFlightFrames) +
                          ", got " + std::to_string(flight.frames));
    }
    validate(flight, 0);
    const Seafloor floor(flight.seed, flight.relief);
    for (int i = 0; i < flight.frames; ++i) check_clearance(flight, floor, i);
}

Frame render_flight_frame(const FlightParams& flight, int index, const Parallel& par) {
    validate(flight, index);
    const Seafloor floor(flight.seed, flight.relief);
    check_clearance(flight, floor, index);
    const FlightPose pose = flight_pose(flight, index);

    const Camera& cam = flight.camera;
    Frame out{Image(cam.width, cam.height, 3), Image(cam.width, cam.height, 1)};
    auto world = [&](const Vec3& r) {
        return pose.right * r.x + pose.down * r.y + pose.forward * r.z;
    };
    const Vec3 o = pose.origin;
    // Colour is the mean albedo at 2x2 sub-pixel rays; their hit points are taken on the
    // horizontal plane through the centre ray's hit (albedo depends on x, y only, and the
    // sub-pixel spread is millimetres), which saves four ray marches per pixel.
    constexpr double kSub[4][2] = {{-0.25, -0.25}, {0.25, -0.25}, {-0.25, 0.25}, {0.25, 0.25}};

    parallel_for(
        std::size_t(cam.height),
        [&](std::size_t v0, std::size_t v1) {
            for (int v = int(v0); v != int(v1); ++v) {
                float* rgb = out.rgb.row(v);
                float* depth = out.depth.row(v);
                for (int u = 0; u < cam.width; ++u) {
                    const Vec3 d = world(cam.ray(u, v));
                    const double t = floor.intersect(o, d, flight.max_range);
                    if (t < 0.0) continue;  // open water: depth 0, colour black
                    depth[u] = float(t);    // camera z of the hit, since the ray's z is 1
                    const double hz = o.z + t * d.z;
                    double sx[4], sy[4];
                    for (int k = 0; k < 4; ++k) {
                        const Vec3 ds = world(cam.ray(u + kSub[k][0], v + kSub[k][1]));
                        double ts = ds.z < 0.0 ? (hz - o.z) / ds.z : t;
                        ts = std::clamp(ts, 0.5 * t, 2.0 * t);
                        sx[k] = o.x + ts * ds.x;
                        sy[k] = o.y + ts * ds.y;
                    }
                    const Rgb c = floor.mean_albedo(sx, sy, 4);
                    rgb[3 * u + 0] = float(c.r);
                    rgb[3 * u + 1] = float(c.g);
                    rgb[3 * u + 2] = float(c.b);
                }
            }
        },
        par.or_grain(4));
    return out;
}

}  // namespace deepsea
