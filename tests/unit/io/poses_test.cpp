// TUM trajectories (io/poses.h): the quaternion's rotation against one written from angles,
// comments and blank lines, and every bad line named by file and line.

#include "deepsea/io/poses.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../message_of.h"
#include "deepsea/core/error.h"

namespace deepsea {

TEST(TumPoses, QuaternionGivesTheCameraAxesInTheWorld) {
    // A rotation by angle a about the unit axis k maps the camera's axes e_i to
    // e_i cos a + (k x e_i) sin a + k (k . e_i) (1 - cos a) (Rodrigues).
    const Vec3 k = normalize(Vec3{0.3, -0.5, 0.8});
    const double a = 1.1;
    const double s = std::sin(a / 2);
    char line[256];
    std::snprintf(line, sizeof line, "1305031102.175304 1.5 -2 0.25 %.17g %.17g %.17g %.17g\n",
                  k.x * s, k.y * s, k.z * s, std::cos(a / 2));
    const std::string text = "# timestamp tx ty tz qx qy qz qw\n\n" + std::string(line) +
                             "  # a comment\n2.5 0 0 0 0 0 0 1\n";
    const auto poses = parse_tum_poses(text, "t.txt");
    ASSERT_EQ(poses.size(), 2u);
    EXPECT_DOUBLE_EQ(poses[0].timestamp, 1305031102.175304);
    EXPECT_EQ(poses[0].pose.origin.x, 1.5);
    EXPECT_EQ(poses[0].pose.origin.y, -2.0);
    const auto rotate = [&](const Vec3& e) {
        return e * std::cos(a) + cross(k, e) * std::sin(a) + k * (dot(k, e) * (1 - std::cos(a)));
    };
    const Vec3 got[3] = {poses[0].pose.right, poses[0].pose.down, poses[0].pose.forward};
    const Vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; ++i) {
        const Vec3 want = rotate(axes[i]);
        EXPECT_NEAR(got[i].x, want.x, 1e-12) << i;
        EXPECT_NEAR(got[i].y, want.y, 1e-12) << i;
        EXPECT_NEAR(got[i].z, want.z, 1e-12) << i;
    }
    EXPECT_EQ(poses[1].pose.forward.z, 1.0);  // the identity
}

TEST(TumPoses, BadLinesNameFileAndLine) {
    const struct {
        std::string text, starts;
    } cases[] = {
        {"1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", "t.txt:2: expected 8 numbers"},
        {"# c\n1 0 0 x 0 0 0 1\n", "t.txt:2: 'x' is not a finite number"},
        {"1 0 0 0 0 0 0 1 9\n", "t.txt:1: expected 8 numbers"},
        {"1 0 0 nan 0 0 0 1\n", "t.txt:1: 'nan' is not a finite number"},
        {"1 0 0 0 0 0 0 2\n", "t.txt:1: the quaternion"},
        {"# only comments\n\n", "t.txt: no poses"},
    };
    for (const auto& c : cases) {
        const std::string m =
            test::message_of<InputError>([&] { parse_tum_poses(c.text, "t.txt"); });
        EXPECT_EQ(m.rfind(c.starts, 0), 0u) << c.text << " -> " << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    }
}

}  // namespace deepsea
