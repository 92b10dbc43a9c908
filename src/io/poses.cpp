#include "deepsea/io/poses.h"

#include <cmath>
#include <sstream>

#include "deepsea/core/error.h"
#include "deepsea/core/input_file.h"

namespace deepsea {

std::vector<TimedPose> parse_tum_poses(const std::string& text, const std::string& file) {
    std::vector<TimedPose> out;
    std::istringstream in(text);
    std::string line;
    int n = 0;
    while (std::getline(in, line)) {
        ++n;
        if (!line.empty() && line.back() == '\r') line.pop_back();
        const auto first = line.find_first_not_of(" \t");
        if (first == std::string::npos || line[first] == '#') continue;
        const auto fail = [&](const std::string& why) {
            return InputError(file + ":" + std::to_string(n) + ": " + why);
        };
        std::istringstream fields(line);
        std::vector<double> v;
        std::string word;
        while (fields >> word) {
            std::size_t used = 0;
            double x = 0.0;
            try {
                x = std::stod(word, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != word.size() || !std::isfinite(x))
                throw fail("'" + word + "' is not a finite number");
            v.push_back(x);
        }
        if (v.size() != 8)
            throw fail("expected 8 numbers, timestamp tx ty tz qx qy qz qw, got " +
                       std::to_string(v.size()));
        const double qx = v[4], qy = v[5], qz = v[6], qw = v[7];
        const double norm = std::sqrt(qx * qx + qy * qy + qz * qz + qw * qw);
        if (!(std::fabs(norm - 1.0) <= 1e-3))
            throw fail("the quaternion qx qy qz qw has length " + std::to_string(norm) + ", not 1");
        const double x = qx / norm, y = qy / norm, z = qz / norm, w = qw / norm;
        // The rotation's columns: the camera's x, y and z axes in the world.
        TimedPose p;
        p.timestamp = v[0];
        p.pose.origin = {v[1], v[2], v[3]};
        p.pose.right = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)};
        p.pose.down = {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)};
        p.pose.forward = {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
        out.push_back(p);
    }
    if (out.empty())
        throw InputError(file + ": no poses (expected lines of timestamp tx ty tz qx qy qz qw)");
    return out;
}

std::vector<TimedPose> load_tum_poses(const std::string& path) {
    return parse_tum_poses(read_text_file(path, "a trajectory file"), path);
}

}  // namespace deepsea
