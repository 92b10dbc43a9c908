#pragma once
// Ports for the runtime's port tests (optics/port.h): a flat port and a dome port from their
// few numbers, the other keys at their defaults.

#include "deepsea/core/vec.h"
#include "deepsea/optics/port.h"

namespace deepsea::test {

inline Port flat_port(Vec3 normal, double distance, double glass) {
    Port p;
    p.kind = PortKind::Flat;
    p.flat.normal = normal;
    p.flat.distance = distance;
    p.flat.glass_thickness = glass;
    return p;
}

inline Port dome_port(Vec3 centre, double radius, double glass) {
    Port p;
    p.kind = PortKind::Dome;
    p.dome.centre = centre;
    p.dome.radius = radius;
    p.dome.glass_thickness = glass;
    return p;
}

}  // namespace deepsea::test
