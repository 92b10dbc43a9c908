// deepsea import-config: a DeepSeaRenderer (Song et al.) configuration file converted into
// deepsea's camera / rig / water YAML, with a comment on every conversion.

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "commands.h"
#include "deepsea/core/error.h"
#include "deepsea/core/vec.h"

namespace deepsea::cli {

namespace {

namespace fs = std::filesystem;

struct Reader {
    std::string file;
    YAML::Node root;

    YAML::Node need(const char* key) const {
        const YAML::Node n = root[key];
        if (!n) throw ConfigError(file + ": " + key + ": missing (not a DeepSeaRenderer config?)");
        return n;
    }
    [[noreturn]] void bad(const char* key, const std::string& problem) const {
        throw ConfigError(file + ":" + std::to_string(root[key].Mark().line + 1) + ": " + key +
                          ": " + problem);
    }
    std::vector<double> numbers(const char* key, std::size_t n) const {
        const YAML::Node v = need(key);
        if (!v.IsSequence() || v.size() != n) {
            bad(key, "expected a list of " + std::to_string(n) + " numbers");
        }
        std::vector<double> out;
        try {
            for (const auto& x : v) out.push_back(x.as<double>());
        } catch (const YAML::Exception&) {
            bad(key, "expected numbers");
        }
        return out;
    }
    std::vector<std::vector<double>> rows(const char* key, std::size_t count, std::size_t n) const {
        const YAML::Node v = need(key);
        if (!v.IsSequence() || v.size() != count) {
            bad(key, "expected " + std::to_string(count) + " entries (num_lights)");
        }
        std::vector<std::vector<double>> out;
        try {
            for (const auto& r : v) {
                if (!r.IsSequence() || r.size() != n) bad(key, "each entry needs " + std::to_string(n) + " numbers");
                std::vector<double> row;
                for (const auto& x : r) row.push_back(x.as<double>());
                out.push_back(row);
            }
        } catch (const YAML::Exception&) {
            bad(key, "expected numbers");
        }
        return out;
    }
    int integer(const char* key) const {
        try {
            return need(key).as<int>();
        } catch (const YAML::Exception&) {
            bad(key, "expected an integer");
        }
    }
};

/// Unit axis of a lamp from DeepSeaRenderer's roll, pitch, yaw (radians): +z (the camera's
/// optical axis) rotated about x by roll, then y by pitch, then z by yaw. With their test-set
/// values (0, +-0.536, 0) this turns each lamp 0.536 rad toward the optical axis, as their
/// README describes ("yawed toward the centre": the rotation is about the camera's y axis).
Vec3 axis_from_rpy(double roll, double pitch, double yaw) {
    const Vec3 a{0.0, -std::sin(roll), std::cos(roll)};
    const Vec3 b{a.x * std::cos(pitch) + a.z * std::sin(pitch), a.y,
                 -a.x * std::sin(pitch) + a.z * std::cos(pitch)};
    return {b.x * std::cos(yaw) - b.y * std::sin(yaw), b.x * std::sin(yaw) + b.y * std::cos(yaw), b.z};
}

std::string convert(const std::string& path) {
    Reader r{path, {}};
    if (!fs::exists(path)) throw IoError("cannot read " + path + ": no such file");
    try {
        r.root = YAML::LoadFile(path);
    } catch (const YAML::BadFile&) {
        throw IoError("cannot read " + path);
    } catch (const YAML::Exception& e) {
        throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
    }
    if (!r.root.IsMap() || !r.root["camera_intrinsic_matrix"]) {
        throw ConfigError(path + ": not a DeepSeaRenderer config (no camera_intrinsic_matrix)");
    }
    const auto K = r.numbers("camera_intrinsic_matrix", 9);
    const auto wh = r.numbers("image_width_height", 2);
    const int n = r.integer("num_lights");
    if (n < 1) r.bad("num_lights", "must be >= 1");
    const auto pos = r.rows("light_positions_XYZ", n, 3);
    const auto rpy = r.rows("light_orientations_RollPitchYaw", n, 3);
    const auto spectrum = r.numbers("light_spectrum_RGB", 3);
    const auto kd = r.numbers("water_attenuation_RGB", 3);
    const int rid_type = r.integer("light_RID_type");
    const int vsf = r.integer("vsf_type");

    std::ostringstream y;
    y.precision(9);
    y << "# Converted by `deepsea import-config` from " << fs::path(path).filename().string()
      << " (DeepSeaRenderer, Song et al.).\n\n";
    y << "# camera_intrinsic_matrix [fx 0 cx; 0 fy cy; 0 0 1] and image_width_height; both\n"
         "# renderers put pixel centres at integer coordinates.\n";
    y << "camera:\n  width: " << int(wh[0]) << "\n  height: " << int(wh[1]) << "\n  fx: " << K[0]
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
        y << "      intensity: [" << spectrum[0] << ", " << spectrum[1] << ", " << spectrum[2] << "]\n";
        if (rid_type == 1) {
            y << "      # light_RID_type 1 is their lab-measured RID table, which is not in the\n"
                 "      # config file: the Gaussian of their type 0 (sigma 35 deg) stands in.\n";
        }
        y << "      rid: {gaussian: {sigma_deg: 35}}\n";
    }
    y << "\n";
    const bool ib = std::fabs(kd[0] - 0.37) <= 0.05 * 0.37 && std::fabs(kd[1] - 0.044) <= 0.05 * 0.044 &&
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
        case 1: y << "  phase: {petzold: clear}\n"; break;
        case 2: y << "  phase: {petzold: coastal}\n"; break;
        case 3: y << "  phase: {petzold: turbid}\n"; break;
        case 4: y << "  phase: {henyey_greenstein: {g: 0.9}}  # their H-G option; g not in the file\n"; break;
        default: r.bad("vsf_type", "expected 1, 2, 3 or 4");
    }
    y << "  forward_scatter: on\n\n";
    y << "# Not converted (no deepsea counterpart):\n"
         "#   scale_factor, scale_factor_bs: ad-hoc gains for direct and backscatter; deepsea keeps\n"
         "#     both in radiance and applies one exposure.\n"
         "#   volumetric_max_depth, num_volumetric_slabs, slab_sampling_method: their slab table;\n"
         "#     deepsea bakes exact cumulative integrals (deepsea bake --z-max/--depth-samples).\n"
         "#   white_balance, auto_iso: camera processing after rendering.\n"
         "#   light_ambient_RGB: Phong ambient; there is no ambient light at 3,000 m.\n"
         "#   depth_smooth_window_size, refine_depth: input clean-up, not part of the model.\n"
         "#   render_back_scatter, write_slab, write_uw_img_in_exr: output switches (see render).\n";
    return y.str();
}

struct ImportArgs {
    std::string input, output;
};

void run(const ImportArgs& a) {
    const std::string text = convert(a.input);
    if (a.output.empty()) {
        std::fputs(text.c_str(), stdout);
        return;
    }
    const fs::path out(a.output);
    const fs::path tmp = out.parent_path() / ("." + out.filename().string() + ".tmp-" +
                                              std::to_string(::getpid()));
    {
        std::ofstream f(tmp);
        f << text;
        f.close();
        if (!f) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw IoError("cannot write " + a.output);
        }
    }
    std::error_code ec;
    fs::rename(tmp, out, ec);
    if (ec) {
        fs::remove(tmp, ec);
        throw IoError("cannot write " + a.output + ": " + ec.message());
    }
    std::printf("wrote %s\n", a.output.c_str());
}

}  // namespace

void setup_import_config(CLI::App& sub) {
    auto a = std::make_shared<ImportArgs>();
    sub.add_option("config", a->input, "DeepSeaRenderer config (YAML)")->required();
    sub.add_option("-o,--output", a->output, "deepsea setup YAML to write (default: stdout)");
    sub.callback([a] { run(*a); });
}

}  // namespace deepsea::cli
