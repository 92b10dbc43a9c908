#include "deepsea/io/import_config.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

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

std::string convert(const Document& doc) {
    // Their files hold many keys deepsea has no use for (listed at the end of the output), and
    // other versions may add more: only the keys read below are checked.
    if (!doc.root().node.IsMap() || !doc.root().node["camera_intrinsic_matrix"])
        doc.fail(doc.root(), "not a DeepSeaRenderer config (no camera_intrinsic_matrix)");
    const MapView m(doc, doc.root(), std::nullopt);
    const auto K = doc.numbers(m.need("camera_intrinsic_matrix"), 9, "");
    const auto wh = doc.list(m.need("image_width_height"));
    if (wh.size() != 2)
        doc.fail(m.need("image_width_height"), "expected a list of 2 integers [width, height]");
    const int width = doc.integer(wh[0]), height = doc.integer(wh[1]);
    const Field& nf = m.need("num_lights");
    const int n = doc.integer(nf);
    if (n < 1) doc.fail(nf, "must be >= 1");
    const auto pos = rows(doc, m.need("light_positions_XYZ"), n, 3);
    const auto rpy = rows(doc, m.need("light_orientations_RollPitchYaw"), n, 3);
    const auto spectrum = doc.numbers(m.need("light_spectrum_RGB"), 3, "r, g, b");
    const auto kd = doc.numbers(m.need("water_attenuation_RGB"), 3, "r, g, b");
    const int rid_type = doc.integer(m.need("light_RID_type"));
    const Field& vf = m.need("vsf_type");
    const int vsf = doc.integer(vf);

    std::ostringstream y;
    y.precision(9);
    y << "# Converted by `deepsea import-config` from " << fs::path(doc.file()).filename().string()
      << " (DeepSeaRenderer, Song et al.).\n\n";
    y << "# camera_intrinsic_matrix [fx 0 cx; 0 fy cy; 0 0 1] and image_width_height; both\n"
         "# renderers put pixel centres at integer coordinates.\n";
    y << "camera:\n  width: " << width << "\n  height: " << height << "\n  fx: " << K[0]
      << "\n  fy: " << K[4] << "\n  cx: " << K[2] << "\n  cy: " << K[5] << "\n\n";
    y << "# light_positions_XYZ are camera-frame metres as in deepsea. Directions: +z (the\n"
         "# optical axis) rotated by light_orientations_RollPitchYaw (about x, then y, then z).\n"
         "# light_spectrum_RGB (relative) becomes the intensity in W/sr; their scale_factor is an\n"
         "# ad-hoc brightness that deepsea's exposure replaces.\n";
    y << "rig:\n  name: deepsearenderer\n  lights:\n";
    for (int i = 0; i < n; ++i) {
        const Vec3 d = axis_from_rpy(rpy[i][0], rpy[i][1], rpy[i][2]);
        y << "    - name: light" << i + 1 << "  # rpy (" << rpy[i][0] << ", " << rpy[i][1] << ", "
          << rpy[i][2] << ") rad\n";
        y << "      position: [" << pos[i][0] << ", " << pos[i][1] << ", " << pos[i][2] << "]\n";
        y << "      direction: [" << d.x << ", " << d.y << ", " << d.z << "]\n";
        y << "      intensity: [" << spectrum[0] << ", " << spectrum[1] << ", " << spectrum[2]
          << "]\n";
        if (rid_type == 1) {
            y << "      # light_RID_type 1 is their lab-measured RID table, which is not in the\n"
                 "      # config file: the Gaussian of their type 0 (sigma 35 deg) stands in.\n";
        }
        y << "      rid: {gaussian: {sigma_deg: 35}}\n";
    }
    y << "\n";
    const bool ib = std::fabs(kd[0] - 0.37) <= 0.05 * 0.37 &&
                    std::fabs(kd[1] - 0.044) <= 0.05 * 0.044 &&
                    std::fabs(kd[2] - 0.035) <= 0.05 * 0.035;
    y << "water:\n";
    if (ib) {
        y << "  # water_attenuation_RGB (" << kd[0] << ", " << kd[1] << ", " << kd[2]
          << ") are Jerlov IB's *diffuse* Kd (Jerlov 1976),\n"
             "  # not the beam attenuation c that light paths need: use the measured IB preset.\n";
        y << "  name: jerlov-IB\n  preset: jerlov:IB\n";
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
            y << "  phase: {henyey_greenstein: {g: 0.9}}  # their H-G option; g not in the file\n";
            break;
        default:
            doc.fail(vf, "expected 1, 2, 3 or 4");
    }
    y << "  forward_scatter: on\n\n";
    y << "# Not converted (no deepsea counterpart):\n"
         "#   scale_factor, scale_factor_bs: ad-hoc gains for direct and backscatter; deepsea "
         "keeps\n"
         "#     both in radiance and applies one exposure.\n"
         "#   volumetric_max_depth, num_volumetric_slabs, slab_sampling_method: their slab table;\n"
         "#     deepsea bakes exact cumulative integrals (deepsea bake --z-max/--depth-samples).\n"
         "#   white_balance, auto_iso: camera processing after rendering.\n"
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
