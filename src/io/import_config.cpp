#include "deepsea/io/import_config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "camera_config.h"
#include "deepsea/camera/sensor.h"
#include "deepsea/core/atomic_file.h"
#include "deepsea/core/error.h"
#include "deepsea/core/vec.h"
#include "deepsea/io/config.h"
#include "yaml_reader.h"

namespace deepsea {

namespace {

namespace fs = std::filesystem;
using yaml::Document;
using yaml::Field;
using yaml::MapView;

/// Unit axis of a lamp from DeepSeaRenderer's roll, pitch, yaw (radians): +z (the camera's
/// optical axis) rotated about x by roll, then y by pitch, then z by yaw. With their test-set
/// values (0, +-0.536, 0) this turns each lamp 0.536 rad toward the optical axis, as their
/// README describes ("yawed toward the centre": the rotation is about the camera's y axis).
Vec3 axis_from_rpy(double roll, double pitch, double yaw) {
    const Vec3 a{0.0, -std::sin(roll), std::cos(roll)};
    const Vec3 b{a.x * std::cos(pitch) + a.z * std::sin(pitch), a.y,
                 -a.x * std::sin(pitch) + a.z * std::cos(pitch)};
    return {b.x * std::cos(yaw) - b.y * std::sin(yaw), b.x * std::sin(yaw) + b.y * std::cos(yaw),
            b.z};
}

/// Their pinhole: fx, fy, cx, cy in pixels.
struct Intrinsics {
    double fx, fy, cx, cy;
    bool from_fov;  ///< given as a field of view
};

/// camera_intrinsic_matrix is either K = [fx 0 cx; 0 fy cy; 0 0 1], row by row, or one number
/// (a one-element list in their files; a bare number is taken too): the horizontal field of
/// view in radians, for which their renderer sets f = width / 2 / tan(fov / 2) and puts the
/// principal point at (width / 2, height / 2).
Intrinsics read_intrinsics(const Document& doc, const Field& f, int width, int height) {
    std::vector<double> k;
    if (f.node.IsScalar()) {
        k.push_back(doc.number(f));
    } else {
        const std::size_t n = doc.list(f).size();
        if (n != 1 && n != 9)
            doc.fail(f,
                     "expected a list of 9 numbers (K row by row) or 1 (the horizontal "
                     "field of view in radians), got " +
                         std::to_string(n));
        k = doc.numbers(f, n, "");
    }
    if (k.size() == 9) return {k[0], k[4], k[2], k[5], false};
    const double fov = k[0];
    if (!(fov > 0.0 && fov < M_PI))
        doc.fail(f, "field of view must be in (0, pi) radians, got " + yaml::fmt(fov));
    const double focal = width / 2.0 / std::tan(fov / 2.0);
    return {focal, focal, width / 2.0, height / 2.0, true};
}

/// The Kd triplets their configs name for Jerlov water types (testset_bomb's comment), which
/// deepsea maps to its measured presets of the same type.
struct KdWater {
    const char* type;
    double r, g, b;
};
constexpr KdWater kTheirKd[] = {{"IB", 0.37, 0.044, 0.035}, {"II", 0.4, 0.071, 0.06}};

/// The Jerlov type whose Kd triplet `kd` matches within 5 % per channel, or nullptr.
const KdWater* jerlov_from_kd(const std::vector<double>& kd) {
    for (const KdWater& w : kTheirKd) {
        const double want[3] = {w.r, w.g, w.b};
        bool match = true;
        for (int c = 0; c < 3; ++c) match = match && std::fabs(kd[c] - want[c]) <= 0.05 * want[c];
        if (match) return &w;
    }
    return nullptr;
}

/// Their light_RID_type 1, "real measurement": the relative intensity of their LED measured in
/// the lab, ten (angle from the lamp's axis in degrees, value) points, from `BXRA_table` in
/// DeepSeaRenderer's src/rendering.cpp (github.com/omv-ysong/DeepSeaRenderer). Their
/// `light_RID` interpolates it linearly and returns 0 beyond 90 degrees, as deepsea's table RID
/// does (0 beyond the last angle, which is 90 with the value 0).
constexpr double kTheirLedAngleDeg[] = {0, 10, 20, 30, 35, 40, 45, 50, 60, 90};
constexpr double kTheirLedValue[] = {1.0, 0.96, 0.87, 0.75, 0.63, 0.5, 0.28, 0.2, 0.12, 0.0};

/// The rig YAML of their light_RID_type: 0, their Gaussian (sigma 35 degrees, 0 beyond 90
/// degrees in their `light_RID`); 1, their measured LED table.
std::string their_rid(int type) {
    std::ostringstream y;
    if (type == 0) {
        y << "      rid: {gaussian: {sigma_deg: 35}}  # light_RID_type 0: their Gaussian\n"
             "      cutoff_deg: 90  # their Gaussian is 0 beyond 90 degrees\n";
        return y.str();
    }
    y << "      # light_RID_type 1: their lab-measured LED (BXRA_table in DeepSeaRenderer's\n"
         "      # src/rendering.cpp), linear between the points, 0 beyond 90 degrees as theirs\n"
         "      rid: {table: {angle_deg: [";
    const char* sep = "";
    for (double a : kTheirLedAngleDeg) y << std::exchange(sep, ", ") << a;
    y << "], value: [";
    sep = "";
    for (double v : kTheirLedValue) y << std::exchange(sep, ", ") << v;
    y << "]}}\n";
    return y.str();
}

/// `count` rows of n numbers each (one per lamp).
std::vector<std::vector<double>> rows(const Document& doc, const Field& f, int count,
                                      std::size_t n) {
    const auto items = doc.list(f);
    if (int(items.size()) != count)
        doc.fail(f, "expected " + std::to_string(count) + " entries (num_lights), got " +
                        std::to_string(items.size()));
    std::vector<std::vector<double>> out;
    for (const Field& r : items) out.push_back(doc.numbers(r, n, ""));
    return out;
}

/// Their camera: white_balance, scale_factor and auto_iso, as their renderer applies them
/// (docs/import-config.md, "Their camera"). Their display value (0-255) is
/// 255 * scale_factor * pi * L for deepsea's radiance L (their albedo is the 8-bit value and
/// their direct term has no 1/pi), times white_balance per channel, clipped at 255, written with
/// no curve. A noise-free camera with an equal response per joule in R, G and B, no falloff, and
/// an exposure whose full well is radiance H / (pi scale_factor) reproduces it with
/// white-balance gains H * white_balance and the linear curve, where H = max(1, 1 / min gain)
/// leaves the raw signal the headroom their clip after white balance has.
void write_camera_stage(std::ostream& y, const Document& doc, const MapView& m) {
    const Field* sf = m.opt("scale_factor");
    if (!sf) return;
    const double scale = doc.number(*sf);
    if (!(scale > 0.0)) doc.fail(*sf, "must be > 0, got " + yaml::fmt(scale));
    std::vector<double> wb{1.0, 1.0, 1.0};
    if (const Field* f = m.opt("white_balance")) {
        wb = doc.numbers(*f, 3, "r, g, b");
        for (double g : wb)
            if (!(g > 0.0)) doc.fail(*f, "each gain must be > 0, got " + yaml::fmt(g));
    }
    const bool auto_iso = m.opt("auto_iso") && doc.boolean(*m.opt("auto_iso"));
    const double headroom = std::max(1.0, 1.0 / std::min({wb[0], wb[1], wb[2]}));

    CameraModel cam;
    cam.lens.vignetting.natural = false;
    Sensor& s = cam.sensor;
    // Equal electrons per joule in every channel: eta_c proportional to 1 / lambda_c.
    for (int c = 0; c < 3; ++c) s.quantum_efficiency[c] = 0.5 * 550.0 / s.wavelength_nm[c];
    s.bits = 16;
    s.full_well = 65535.0;
    s.system_gain = 1.0;
    s.black_level = 0.0;
    s.noise = false;
    const double per_ms = electrons_per_radiance(cam.lens, s, 1, 1.0);
    s.exposure_time_ms = s.full_well * M_PI * scale / headroom / per_ms;
    Processing& p = cam.processing;
    p.curve = OutputCurve::Linear;
    if (!auto_iso) {
        p.white_balance = WhiteBalance::Gains;
        p.gains = Rgb{headroom * wb[0], headroom * wb[1], headroom * wb[2]};
    }

    y << "  # Their camera (docs/import-config.md): a noise-free sensor with the same response\n"
         "  # per joule in R, G and B, no lens falloff, and no output curve, as their renderer.\n"
         "  # scale_factor "
      << scale << ": display value = pi * " << scale
      << " * radiance (their 255 = 1), from the exposure time.\n";
    if (auto_iso) {
        y << "  # auto_iso: true: their writer stretches each frame's [min, max] (all channels\n"
             "  # together) to 0-255 and skips white_balance. The stretch has no counterpart in\n"
             "  # the camera section (deepsea's auto exposure will be it); white balance is off.\n";
    } else {
        y << "  # white_balance [" << wb[0] << ", " << wb[1] << ", " << wb[2]
          << "]: gains after the sensor, clipped at 1 as theirs at 255";
        if (headroom > 1.0) y << " (times " << headroom << ": the raw headroom they have)";
        y << ".\n";
    }
    write_camera_model(y, cam);
}

std::string convert(const Document& doc) {
    // Their files hold many keys deepsea has no use for (listed at the end of the output), and
    // other versions may add more: only the keys read below are checked.
    if (!doc.root().node.IsMap() || !doc.root().node["camera_intrinsic_matrix"])
        doc.fail(doc.root(), "not a DeepSeaRenderer config (no camera_intrinsic_matrix)");
    const MapView m(doc, doc.root(), std::nullopt);
    const auto wh = doc.list(m.need("image_width_height"));
    if (wh.size() != 2)
        doc.fail(m.need("image_width_height"), "expected a list of 2 integers [width, height]");
    const int width = doc.integer(wh[0]), height = doc.integer(wh[1]);
    const Intrinsics K = read_intrinsics(doc, m.need("camera_intrinsic_matrix"), width, height);
    const Field& nf = m.need("num_lights");
    const int n = doc.integer(nf);
    if (n < 1) doc.fail(nf, "must be >= 1");
    const auto pos = rows(doc, m.need("light_positions_XYZ"), n, 3);
    const auto rpy = rows(doc, m.need("light_orientations_RollPitchYaw"), n, 3);
    const auto spectrum = doc.numbers(m.need("light_spectrum_RGB"), 3, "r, g, b");
    const auto kd = doc.numbers(m.need("water_attenuation_RGB"), 3, "r, g, b");
    const Field& rf = m.need("light_RID_type");
    const int rid_type = doc.integer(rf);
    if (rid_type != 0 && rid_type != 1)
        doc.fail(rf, "expected 0 (their Gaussian) or 1 (their lab-measured LED)");
    const Field& vf = m.need("vsf_type");
    const int vsf = doc.integer(vf);

    std::ostringstream y;
    y.precision(9);
    y << "# Converted by `deepsea import-config` from " << fs::path(doc.file()).filename().string()
      << " (DeepSeaRenderer, Song et al.).\n\n";
    if (K.from_fov) {
        y << "# camera_intrinsic_matrix [fov] is their horizontal field of view (radians):\n"
             "# f = width / 2 / tan(fov / 2), principal point (width / 2, height / 2) as their\n"
             "# renderer sets it; both renderers put pixel centres at integer coordinates.\n";
    } else {
        y << "# camera_intrinsic_matrix [fx 0 cx; 0 fy cy; 0 0 1] and image_width_height; both\n"
             "# renderers put pixel centres at integer coordinates.\n";
    }
    y << "camera:\n  width: " << width << "\n  height: " << height << "\n  fx: " << K.fx
      << "\n  fy: " << K.fy << "\n  cx: " << K.cx << "\n  cy: " << K.cy << "\n";
    write_camera_stage(y, doc, m);
    y << "\n";
    y << "# light_positions_XYZ are camera-frame metres as in deepsea. Directions: +z (the\n"
         "# optical axis) rotated by light_orientations_RollPitchYaw (about x, then y, then z).\n"
         "# light_spectrum_RGB (relative) becomes the intensity in W/sr; their scale_factor is "
         "the\n"
         "# camera's exposure above.\n";
    y << "rig:\n  name: deepsearenderer\n  lights:\n";
    for (int i = 0; i < n; ++i) {
        const Vec3 d = axis_from_rpy(rpy[i][0], rpy[i][1], rpy[i][2]);
        y << "    - name: light" << i + 1 << "  # rpy (" << rpy[i][0] << ", " << rpy[i][1] << ", "
          << rpy[i][2] << ") rad\n";
        y << "      position: [" << pos[i][0] << ", " << pos[i][1] << ", " << pos[i][2] << "]\n";
        y << "      direction: [" << d.x << ", " << d.y << ", " << d.z << "]\n";
        y << "      intensity: [" << spectrum[0] << ", " << spectrum[1] << ", " << spectrum[2]
          << "]\n";
        y << their_rid(rid_type);
    }
    y << "\n";
    y << "water:\n";
    if (const KdWater* w = jerlov_from_kd(kd)) {
        const std::string type = w->type;
        y << "  # water_attenuation_RGB (" << kd[0] << ", " << kd[1] << ", " << kd[2]
          << ") are Jerlov " << type
          << "'s *diffuse* Kd (Jerlov 1976),\n"
             "  # not the beam attenuation c that light paths need: use the measured "
          << type << " preset.\n";
        y << "  name: jerlov-" << type << "\n  preset: jerlov:" << type << "\n";
    } else {
        y << "  # water_attenuation_RGB taken as the beam attenuation c. If these are diffuse Kd\n"
             "  # values (as the authors' examples are), c is larger and this water too clear.\n";
        y << "  name: deepsearenderer\n  attenuation: [" << kd[0] << ", " << kd[1] << ", " << kd[2]
          << "]\n";
    }
    y << "  # vsf_type " << vsf << "\n";
    switch (vsf) {
        case 1:
            y << "  phase: {petzold: clear}\n";
            break;
        case 2:
            y << "  phase: {petzold: coastal}\n";
            break;
        case 3:
            y << "  phase: {petzold: turbid}\n";
            break;
        case 4:
            // Their H-G is (1 - g^2) / (4 pi (1 + g^2 + 2 g cos psi)^1.5) with g = -0.3 and psi
            // the scattering angle: the standard form (- 2 g cos psi) with g = +0.3.
            y << "  # their Henyey-Greenstein: g = -0.3 in their code's sign convention\n"
                 "  # (1 + g^2 + 2 g cos psi), which is g = +0.3 in the standard one\n";
            y << "  phase: {henyey_greenstein: {g: 0.3}}\n";
            break;
        default:
            doc.fail(vf, "expected 1, 2, 3 or 4");
    }
    y << "  forward_scatter: on\n\n";
    y << "# Not converted (no deepsea counterpart):\n"
         "#   scale_factor_bs: an extra gain on their backscatter alone; deepsea keeps direct\n"
         "#     and backscatter in the same radiance under one exposure (scale_factor, above).\n"
         "#   volumetric_max_depth, num_volumetric_slabs, slab_sampling_method: their slab table;\n"
         "#     deepsea bakes exact cumulative integrals (deepsea bake --z-max/--depth-samples).\n"

         "#   light_ambient_RGB: Phong ambient; there is no ambient light at 3,000 m.\n"
         "#   depth_smooth_window_size, refine_depth: input clean-up, not part of the model.\n"
         "#   render_back_scatter, write_slab, write_uw_img_in_exr: output switches (see "
         "render).\n";
    return y.str();
}

}  // namespace

std::string import_config(const std::string& path) {
    const std::string text = convert(Document::load(path));
    // Values their renderer accepts but deepsea's schema does not (a zero focal length, a
    // negative intensity) surface here, with the line in the converted text.
    parse_setup(text, path + " (converted)");
    return text;
}

void import_config(const std::string& path, const std::string& output) {
    require_distinct(output, {{path, "the input"}});
    write_text_atomically(output, import_config(path));
}

}  // namespace deepsea
