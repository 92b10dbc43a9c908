#include "deepsea/bake/bake_ray.h"

#include <string>

#include "deepsea/core/error.h"

namespace deepsea {

BakeRay bake_ray(const Camera& camera, const std::optional<Port>& port, double u, double v) {
    BakeRay r;
    if (!port) {
        const Vec3 ray = camera.ray(u, v);
        r.stretch = length(ray);
        r.dir = ray / r.stretch;
        return r;
    }
    const PortRay p = trace_port(*port, camera, u, v);
    const std::string where = "camera.port: the ray through image point (u, v) = (" +
                              short_number(u) + ", " + short_number(v) + ")";
    if (!p.valid()) throw ConfigError(where + " has no water-side ray (docs/ports.md)");
    r.port = true;
    r.origin = p.origin;
    r.dir = p.direction[1];
    if (!(r.dir.z > 0.0))
        throw ConfigError(where +
                          " leaves the port sideways or backwards (its water-side "
                          "direction's z is " +
                          short_number(r.dir.z) + "): a lattice in planar depth cannot hold it");
    return r;
}

}  // namespace deepsea
