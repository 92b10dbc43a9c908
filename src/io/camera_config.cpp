#include "camera_config.h"

#include "deepsea/camera/bayer.h"
#include "deepsea/camera/distortion.h"
#include "deepsea/camera/presets.h"
#include "deepsea/optics/schema.h"

namespace deepsea {

namespace {

using yaml::Document;
using yaml::Field;
using yaml::fmt;
using yaml::join;
using yaml::MapView;

// ---------------------------------------------------------------------------------------------
// camera.lens, camera.sensor, camera.processing, camera.auto_exposure (units, defaults and
// ranges: docs/camera.md;
// the ranges are checked by validate(CameraModel) in the camera layer)
//
//   lens.f_number, lens.transmittance,
//   lens.focus_distance_m                              numbers
//   lens.vignetting: {natural: bool, k1, k2, k3}       numbers
//   lens.distortion: {k1, k2, p1, p2, k3}              OpenCV's distCoeffs
//   sensor.preset                                      a name (camera/presets.h), read first:
//                                                      the other sensor keys override it
//   sensor.pixel_pitch_um, exposure_time_ms, full_well, dark_noise, dark_current, dsnu,
//          prnu_percent, black_level                   numbers
//   sensor.quantum_efficiency, wavelength_nm           [r, g, b]
//   sensor.system_gain | sensor.iso                    a number (not both)
//   sensor.bits, sensor.seed                           integers (seed >= 0)
//   sensor.noise                                       bool
//   sensor.bayer                                       none | rggb | bggr | grbg | gbrg
//   processing.white_balance                           none | grey_world | {gains: [r, g, b]}
//   processing.matrix                                  9 numbers, row-major
//   processing.curve                                   linear | srgb | {gamma: g}
//   auto_exposure.enabled                              bool; true when the map is given
//   auto_exposure.metering                             mean | {percentile: p}
//   auto_exposure.target, damping, min_exposure_time_ms, max_exposure_time_ms,
//          min_system_gain, max_system_gain            numbers

void parse_lens(const Document& doc, const Field& f, Lens& lens) {
    const MapView m(doc, f, camera_schema::kLens);
    if (const Field* x = m.opt("f_number")) lens.f_number = doc.number(*x);
    if (const Field* x = m.opt("transmittance")) lens.transmittance = doc.number(*x);
    if (const Field* x = m.opt("focus_distance_m")) lens.focus_distance_m = doc.number(*x);
    if (const Field* v = m.opt("vignetting")) {
        const MapView vm(doc, *v, camera_schema::kVignetting);
        Vignetting& g = lens.vignetting;
        if (const Field* x = vm.opt("natural")) g.natural = doc.boolean(*x);
        if (const Field* x = vm.opt("k1")) g.k1 = doc.number(*x);
        if (const Field* x = vm.opt("k2")) g.k2 = doc.number(*x);
        if (const Field* x = vm.opt("k3")) g.k3 = doc.number(*x);
    }
    if (const Field* d = m.opt("distortion")) {
        const MapView dm(doc, *d, camera_schema::kDistortion);
        Distortion& k = lens.distortion;
        for (const auto& [key, value] :
             {std::pair{"k1", &k.k1}, std::pair{"k2", &k.k2}, std::pair{"p1", &k.p1},
              std::pair{"p2", &k.p2}, std::pair{"k3", &k.k3}})
            if (const Field* x = dm.opt(key)) *value = doc.number(*x);
    }
}

void parse_sensor(const Document& doc, const Field& f, Sensor& s) {
    const MapView m(doc, f, camera_schema::kSensor);
    // A preset first: the keys below override its values.
    if (const Field* x = m.opt("preset")) {
        try {
            s = sensor_preset(doc.string(*x));
        } catch (const SchemaError& e) {
            doc.fail(*x, e.problem());
        }
    }
    for (const auto& [key, value] :
         {std::pair{"pixel_pitch_um", &s.pixel_pitch_um},
          std::pair{"exposure_time_ms", &s.exposure_time_ms}, std::pair{"iso", &s.iso},
          std::pair{"full_well", &s.full_well}, std::pair{"dark_noise", &s.dark_noise},
          std::pair{"dark_current", &s.dark_current}, std::pair{"dsnu", &s.dsnu},
          std::pair{"prnu_percent", &s.prnu_percent}})
        if (const Field* x = m.opt(key)) *value = doc.number(*x);
    if (const Field* x = m.opt("quantum_efficiency")) s.quantum_efficiency = doc.rgb(*x);
    if (const Field* x = m.opt("wavelength_nm")) s.wavelength_nm = doc.rgb(*x);
    if (m.has("system_gain") && m.has("iso"))
        doc.fail(*m.opt("iso"), "give system_gain or iso, not both");
    if (const Field* x = m.opt("system_gain")) s.system_gain = doc.number(*x);
    if (const Field* x = m.opt("bits")) s.bits = doc.integer(*x);
    if (const Field* x = m.opt("black_level")) s.black_level = doc.number(*x);
    if (const Field* x = m.opt("noise")) s.noise = doc.boolean(*x);
    if (const Field* x = m.opt("seed")) {
        const int seed = doc.integer(*x);
        if (seed < 0) doc.fail(*x, "must be >= 0, got " + std::to_string(seed));
        s.seed = std::uint64_t(seed);
    }
    if (const Field* x = m.opt("bayer")) {
        const std::string name = doc.string(*x);
        const std::optional<BayerPattern> p = bayer_from_name(name);
        if (!p) doc.fail(*x, "unknown Bayer pattern '" + name + "'; known: " + bayer_names());
        s.bayer = *p;
    }
}

void parse_processing(const Document& doc, const Field& f, Processing& p) {
    const MapView m(doc, f, camera_schema::kProcessing);
    if (const Field* wb = m.opt("white_balance")) {
        if (wb->node.IsMap()) {
            const MapView gm(doc, *wb, std::vector<std::string>{"gains"});
            p.white_balance = WhiteBalance::Gains;
            p.gains = doc.rgb(gm.need("gains"));
        } else {
            const std::string v = doc.string(*wb);
            if (v == "none")
                p.white_balance = WhiteBalance::None;
            else if (v == "grey_world")
                p.white_balance = WhiteBalance::GreyWorld;
            else
                doc.fail(*wb, "expected none, grey_world or {gains: [r, g, b]}, got '" + v + "'");
        }
    }
    if (const Field* x = m.opt("matrix")) {
        const std::vector<double> v = doc.numbers(*x, 9, "numbers (a 3x3 matrix, row-major)");
        std::array<double, 9> a{};
        for (int i = 0; i < 9; ++i) a[i] = v[i];
        p.matrix = a;
    }
    if (const Field* c = m.opt("curve")) {
        if (c->node.IsMap()) {
            const MapView cm(doc, *c, std::vector<std::string>{"gamma"});
            p.curve = OutputCurve::Gamma;
            p.gamma = doc.number(cm.need("gamma"));
        } else {
            const std::string v = doc.string(*c);
            if (v == "linear")
                p.curve = OutputCurve::Linear;
            else if (v == "srgb")
                p.curve = OutputCurve::Srgb;
            else
                doc.fail(*c, "expected linear, srgb or {gamma: g}, got '" + v + "'");
        }
    }
}

void parse_auto_exposure(const Document& doc, const Field& f, AutoExposure& a) {
    const MapView m(doc, f, camera_schema::kAutoExposure);
    a.enabled = true;  // the map given: on, unless it says otherwise
    if (const Field* x = m.opt("enabled")) a.enabled = doc.boolean(*x);
    if (const Field* x = m.opt("metering")) {
        if (x->node.IsMap()) {
            const MapView pm(doc, *x, std::vector<std::string>{"percentile"});
            a.metering = Metering::Percentile;
            a.percentile = doc.number(pm.need("percentile"));
        } else {
            const std::string v = doc.string(*x);
            if (v != "mean") doc.fail(*x, "expected mean or {percentile: p}, got '" + v + "'");
            a.metering = Metering::Mean;
        }
    }
    for (const auto& [key, value] :
         {std::pair{"target", &a.target}, std::pair{"damping", &a.damping},
          std::pair{"min_exposure_time_ms", &a.min_exposure_time_ms},
          std::pair{"max_exposure_time_ms", &a.max_exposure_time_ms}})
        if (const Field* x = m.opt(key)) *value = doc.number(*x);
    if (const Field* x = m.opt("min_system_gain")) a.min_system_gain = doc.number(*x);
    if (const Field* x = m.opt("max_system_gain")) a.max_system_gain = doc.number(*x);
}

std::string triple(const Rgb& v) {
    return "[" + fmt(v.r) + ", " + fmt(v.g) + ", " + fmt(v.b) + "]";
}

}  // namespace

std::optional<CameraModel> parse_camera_model(const Document& doc, const MapView& m,
                                              const Camera& intrinsics) {
    const Field *lens = m.opt("lens"), *sensor = m.opt("sensor"), *proc = m.opt("processing"),
                *ae = m.opt("auto_exposure");
    if (!lens && !sensor && !proc && !ae) return std::nullopt;
    CameraModel model;
    if (lens) parse_lens(doc, *lens, model.lens);
    if (sensor) parse_sensor(doc, *sensor, model.sensor);
    if (proc) parse_processing(doc, *proc, model.processing);
    if (ae) parse_auto_exposure(doc, *ae, model.auto_exposure);
    validate(model);
    check_distortion(model.lens.distortion, intrinsics);
    return model;
}

void write_camera_model(std::ostream& o, const CameraModel& model) {
    const Lens& l = model.lens;
    const Vignetting& v = l.vignetting;
    const Distortion& d = l.distortion;
    o << "  lens:\n"
      << "    f_number: " << fmt(l.f_number) << "\n"
      << "    transmittance: " << fmt(l.transmittance) << "\n"
      << "    focus_distance_m: " << fmt(l.focus_distance_m) << "\n"
      << "    vignetting: {natural: " << (v.natural ? "true" : "false") << ", k1: " << fmt(v.k1)
      << ", k2: " << fmt(v.k2) << ", k3: " << fmt(v.k3) << "}\n"
      << "    distortion: {k1: " << fmt(d.k1) << ", k2: " << fmt(d.k2) << ", p1: " << fmt(d.p1)
      << ", p2: " << fmt(d.p2) << ", k3: " << fmt(d.k3) << "}\n";
    const Sensor& s = model.sensor;
    o << "  sensor:\n"
      << "    pixel_pitch_um: " << fmt(s.pixel_pitch_um) << "\n"
      << "    exposure_time_ms: " << fmt(s.exposure_time_ms) << "\n"
      << "    quantum_efficiency: " << triple(s.quantum_efficiency) << "\n"
      << "    wavelength_nm: " << triple(s.wavelength_nm) << "\n";
    if (s.system_gain)
        o << "    system_gain: " << fmt(*s.system_gain) << "\n";
    else
        o << "    iso: " << fmt(s.iso) << "\n";
    o << "    full_well: " << fmt(s.full_well) << "\n"
      << "    bits: " << s.bits << "\n";
    if (s.black_level) o << "    black_level: " << fmt(*s.black_level) << "\n";
    o << "    dark_noise: " << fmt(s.dark_noise) << "\n"
      << "    dark_current: " << fmt(s.dark_current) << "\n"
      << "    dsnu: " << fmt(s.dsnu) << "\n"
      << "    prnu_percent: " << fmt(s.prnu_percent) << "\n"
      << "    noise: " << (s.noise ? "true" : "false") << "\n"
      << "    seed: " << s.seed << "\n"
      << "    bayer: " << bayer_name(s.bayer) << "\n";
    const Processing& p = model.processing;
    o << "  processing:\n    white_balance: ";
    switch (p.white_balance) {
        case WhiteBalance::None:
            o << "none\n";
            break;
        case WhiteBalance::GreyWorld:
            o << "grey_world\n";
            break;
        case WhiteBalance::Gains:
            o << "{gains: " << triple(p.gains) << "}\n";
            break;
    }
    if (p.matrix) {
        std::vector<std::string> m;
        for (double x : *p.matrix) m.push_back(fmt(x));
        o << "    matrix: [" << join(m) << "]\n";
    }
    o << "    curve: ";
    switch (p.curve) {
        case OutputCurve::Linear:
            o << "linear\n";
            break;
        case OutputCurve::Srgb:
            o << "srgb\n";
            break;
        case OutputCurve::Gamma:
            o << "{gamma: " << fmt(p.gamma) << "}\n";
            break;
    }
    const AutoExposure& a = model.auto_exposure;
    o << "  auto_exposure:\n"
      << "    enabled: " << (a.enabled ? "true" : "false") << "\n"
      << "    metering: "
      << (a.metering == Metering::Mean ? std::string("mean")
                                       : "{percentile: " + fmt(a.percentile) + "}")
      << "\n"
      << "    target: " << fmt(a.target) << "\n"
      << "    damping: " << fmt(a.damping) << "\n"
      << "    min_exposure_time_ms: " << fmt(a.min_exposure_time_ms) << "\n"
      << "    max_exposure_time_ms: " << fmt(a.max_exposure_time_ms) << "\n";
    if (a.min_system_gain) o << "    min_system_gain: " << fmt(*a.min_system_gain) << "\n";
    if (a.max_system_gain) o << "    max_system_gain: " << fmt(*a.max_system_gain) << "\n";
}

}  // namespace deepsea
