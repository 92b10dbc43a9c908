#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "deepsea/core/error.h"
#include "deepsea/optics/camera.h"
#include "deepsea/optics/light.h"

namespace deepsea {

TEST(Camera, RayAndCosPhi) {
    const Camera cam{800, 800, 600, 600, 400, 400};
    const Vec3 r = cam.ray(1000, 400);
    EXPECT_DOUBLE_EQ(r.x, 1.0);
    EXPECT_DOUBLE_EQ(r.z, 1.0);
    EXPECT_NEAR(cam.cos_phi(1000, 400), 1.0 / std::sqrt(2.0), 1e-15);
    EXPECT_DOUBLE_EQ(cam.cos_phi(400, 400), 1.0);
}

TEST(Camera, RangeAndZRoundTrip) {
    const Camera cam{640, 480, 500, 510, 319.5, 239.5};
    for (double u : {0.0, 100.0, 639.0}) {
        for (double v : {0.0, 239.5, 479.0}) {
            const Vec3 Pz = cam.point(u, v, 3.0, DepthKind::Z);
            EXPECT_NEAR(Pz.z, 3.0, 1e-12);
            const double range = length(Pz);
            const Vec3 Pr = cam.point(u, v, range, DepthKind::Range);
            EXPECT_NEAR(length(Pr - Pz), 0.0, 1e-12);
            EXPECT_NEAR(cam.z_depth(u, v, range, DepthKind::Range), 3.0, 1e-12);
        }
    }
}

TEST(Camera, SameViewAtAnotherResolution) {
    const Camera a{800, 800, 600, 600, 399.5, 399.5};
    const Camera half{400, 400, 300, 300, 199.5, 199.5};
    EXPECT_TRUE(a.same_view(half));
    EXPECT_FALSE(a == half);
    Camera other = half;
    other.fx = 310;
    EXPECT_FALSE(a.same_view(other));
}

TEST(FrameCamera, ScalesTheAssetCameraToTheFrameSize) {
    const Camera baked{120, 90, 90.0, 90.0, 59.5, 44.5};
    const Camera c = frame_camera(baked, Camera{}, 60, 45);
    EXPECT_EQ(c.width, 60);
    EXPECT_DOUBLE_EQ(c.fx, baked.fx / 2);
    EXPECT_DOUBLE_EQ(c.cx, 29.5);  // pixel edges scale, centres stay at integers
    EXPECT_TRUE(baked.same_view(c));
    EXPECT_EQ(frame_camera(baked, Camera{}, 120, 90), baked);
    EXPECT_THROW(frame_camera(baked, Camera{}, 60, 60), AssetError);  // another aspect ratio
}

TEST(FrameCamera, RequestedCameraIsCheckedAgainstTheAssetAndTheFrames) {
    const Camera baked{120, 90, 90.0, 90.0, 59.5, 44.5};
    const Camera half{60, 45, 45.0, 45.0, 29.5, 22.0};
    EXPECT_EQ(frame_camera(baked, half, 60, 45), half);
    EXPECT_THROW(frame_camera(baked, half, 120, 90), InputError);  // not the frames' size
    Camera other = half;
    other.fx = 60.0;
    try {
        frame_camera(baked, other, 60, 45);
        FAIL() << "no AssetError";
    } catch (const AssetError& e) {
        const std::string msg = e.what();  // names both cameras on one line
        EXPECT_NE(msg.find(describe(baked)), std::string::npos) << msg;
        EXPECT_NE(msg.find(describe(other)), std::string::npos) << msg;
    }
}

TEST(ToPlanarDepth, RangeBecomesZAndOpenWaterStays) {
    const Camera cam{3, 1, 1.0, 1.0, 1.0, 0.0};
    Image depth(3, 1, 1);
    depth.at(0, 0) = float(2.0 * std::sqrt(2.0));  // ray (-1, 0, 1): z = range / sqrt(2)
    depth.at(1, 0) = 2.0f;                         // on the axis
    depth.at(2, 0) = std::nanf("");
    Image same = depth;
    to_planar_depth(cam, same, DepthKind::Z);
    EXPECT_EQ(same.at(0, 0), depth.at(0, 0));
    to_planar_depth(cam, depth, DepthKind::Range);
    EXPECT_NEAR(depth.at(0, 0), 2.0f, 1e-6f);
    EXPECT_EQ(depth.at(1, 0), 2.0f);
    EXPECT_TRUE(std::isnan(depth.at(2, 0)));
}

TEST(Rid, GaussianInDegrees) {
    Rid rid;  // sigma 35 deg
    EXPECT_DOUBLE_EQ(rid(0.0), 1.0);
    EXPECT_NEAR(rid(35.0 * M_PI / 180.0), std::exp(-0.5), 1e-12);
    rid.cutoff_deg = 30.0;
    EXPECT_EQ(rid(31.0 * M_PI / 180.0), 0.0);
    EXPECT_GT(rid(29.0 * M_PI / 180.0), 0.0);
}

TEST(Rid, TableInterpolatesLinearlyAndEndsAtZero) {
    Rid rid;
    rid.kind = Rid::Kind::Table;
    rid.angle_deg = {0, 10, 40};
    rid.value = {1.0, 0.8, 0.2};
    const double d = M_PI / 180.0;
    EXPECT_DOUBLE_EQ(rid(0.0), 1.0);
    EXPECT_NEAR(rid(5 * d), 0.9, 1e-12);
    EXPECT_NEAR(rid(25 * d), 0.5, 1e-12);
    EXPECT_NEAR(rid(40 * d), 0.2, 1e-12);
    EXPECT_EQ(rid(41 * d), 0.0);
}

TEST(Rid, RowsGiveTheSameBitsAsOneAngleAtATime) {
    // the authors' lamp table, a dense one (several angles a bucket, an angle on a bucket's
    // edge), a cutoff inside the table and a Gaussian; every float angle step over [0, pi],
    // the table's own angles, their neighbours and values beyond the range
    Rid authors;
    authors.kind = Rid::Kind::Table;
    authors.angle_deg = {0, 10, 20, 30, 35, 40, 45, 50, 60, 90};
    authors.value = {1, 0.96, 0.87, 0.75, 0.63, 0.5, 0.28, 0.2, 0.12, 0};
    Rid dense = authors;
    dense.angle_deg = {2.5, 2.6, 2.65, 2.7, 3.0, 3.25, 100.0};
    dense.value = {0.1, 0.9, 0.3, 0.5, 0.7, 0.2, 0.05};
    dense.cutoff_deg = 80.0;
    Rid gaussian;
    std::vector<float> theta;
    for (int k = 0; k <= 200000; ++k) theta.push_back(float(k * M_PI / 200000.0));
    for (const Rid* r : {&authors, &dense})
        for (const double a : r->angle_deg) {
            const float t = float(a * M_PI / 180.0);
            theta.insert(theta.end(), {std::nextafter(t, 0.0f), t, std::nextafter(t, 4.0f)});
        }
    theta.insert(theta.end(), {-1.0f, 0.0f, -0.0f, 3.5f, 1e30f, float(NAN), INFINITY});
    for (const Rid* r : {&authors, &dense, &gaussian}) {
        const RidRows rows(*r);
        std::vector<float> out(theta.size());
        rows(int(theta.size()), theta.data(), out.data());
        for (std::size_t i = 0; i < theta.size(); ++i) {
            const float one = float((*r)(double(theta[i])));
            ASSERT_EQ(std::memcmp(&one, &out[i], sizeof one), 0)
                << "theta " << theta[i] << ": " << one << " one at a time, " << out[i] << " rows";
        }
    }
}

TEST(Light, IntensityTowardUsesTheAngleToTheAxis) {
    Light l;
    l.direction = normalize(Vec3(1, 0, 1));
    l.intensity = {2.0, 1.0, 0.5};
    const Rgb on_axis = l.intensity_toward(l.direction);
    EXPECT_NEAR(on_axis.r, 2.0, 1e-12);
    const Rgb off = l.intensity_toward(Vec3(0, 0, 1));  // 45 degrees off
    EXPECT_NEAR(off.g, std::exp(-0.5 * (45.0 / 35.0) * (45.0 / 35.0)), 1e-12);
}

}  // namespace deepsea
