#include "port_config.h"

#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

using yaml::Document;
using yaml::Field;
using yaml::fmt;
using yaml::MapView;

// ---------------------------------------------------------------------------------------------
// camera.port (docs/config.md, docs/ports.md; ranges checked by optics' validate(Port) and
// check_port_view)
//
//   key                      unit  range                                   default
//   flat | dome              -     a map; exactly one of the two           (no port)
//   flat.normal              -     [x, y, z], finite, non-zero             [0, 0, 1]
//   flat.distance            m     [0, 10]: camera centre to the inner     required
//                                  surface along the normal
//   dome.centre              m     [x, y, z], |centre| < radius            [0, 0, 0]
//   dome.radius              m     (0, 10]: the inner surface's radius     required
//   flat|dome.glass_thickness m    (0, 10]                                 required
//   flat|dome.n_air, n_glass -     > 0                                     1.0, 1.49
//   flat|dome.n_water        -     > 0, one number or [r, g, b]            1.34
//   fresnel                  -     bool: Fresnel transmittance in the      false
//                                  radiance factor

Rgb parse_index(const Document& doc, const Field& f) {
    if (f.node.IsSequence()) return doc.rgb(f);
    return Rgb(doc.number(f));
}

void parse_indices(const Document& doc, const MapView& m, Port& port) {
    if (const Field* x = m.opt("n_air")) port.n_air = doc.number(*x);
    if (const Field* x = m.opt("n_glass")) port.n_glass = doc.number(*x);
    if (const Field* x = m.opt("n_water")) port.n_water = parse_index(doc, *x);
}

std::string triple(const Vec3& v) {
    return "[" + fmt(v.x) + ", " + fmt(v.y) + ", " + fmt(v.z) + "]";
}

}  // namespace

std::optional<Port> parse_port(const Document& doc, const MapView& camera,
                               const Camera& intrinsics) {
    const Field* f = camera.opt("port");
    if (!f) return std::nullopt;
    const MapView m(doc, *f, schema::kPort);
    if (m.has("flat") == m.has("dome"))
        doc.fail(f->key_mark, f->path, "give exactly one of flat, dome");
    Port port;
    if (const Field* flat = m.opt("flat")) {
        const MapView fm(doc, *flat, schema::kFlatPort);
        port.kind = PortKind::Flat;
        if (const Field* x = fm.opt("normal")) port.flat.normal = doc.vec3(*x);
        port.flat.distance = doc.number(fm.need("distance"));
        port.flat.glass_thickness = doc.number(fm.need("glass_thickness"));
        parse_indices(doc, fm, port);
    } else {
        const MapView dm(doc, *m.opt("dome"), schema::kDomePort);
        port.kind = PortKind::Dome;
        if (const Field* x = dm.opt("centre")) port.dome.centre = doc.vec3(*x);
        port.dome.radius = doc.number(dm.need("radius"));
        port.dome.glass_thickness = doc.number(dm.need("glass_thickness"));
        parse_indices(doc, dm, port);
    }
    if (const Field* x = m.opt("fresnel")) port.fresnel = doc.boolean(*x);
    validate(port);
    check_port_view(port, intrinsics);
    return port;
}

void write_port(std::ostream& o, const Port& p) {
    o << "  port:\n    " << p.name() << ":\n";
    if (p.kind == PortKind::Flat)
        o << "      normal: " << triple(p.flat.normal) << "\n"
          << "      distance: " << fmt(p.flat.distance) << "\n"
          << "      glass_thickness: " << fmt(p.flat.glass_thickness) << "\n";
    else
        o << "      centre: " << triple(p.dome.centre) << "\n"
          << "      radius: " << fmt(p.dome.radius) << "\n"
          << "      glass_thickness: " << fmt(p.dome.glass_thickness) << "\n";
    o << "      n_air: " << fmt(p.n_air) << "\n"
      << "      n_glass: " << fmt(p.n_glass) << "\n"
      << "      n_water: ";
    if (p.dispersive())
        o << "[" << fmt(p.n_water.r) << ", " << fmt(p.n_water.g) << ", " << fmt(p.n_water.b)
          << "]\n";
    else
        o << fmt(p.n_water.r) << "\n";
    o << "    fresnel: " << (p.fresnel ? "true" : "false") << "\n";
}

}  // namespace deepsea
