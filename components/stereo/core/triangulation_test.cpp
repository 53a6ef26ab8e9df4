#include "stereo/core/triangulation.hpp"

#include "stereo/core/rectifier.hpp"
#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

TEST(Triangulator, GivenDisparityWhenTriangulatedThenDepthIsFocalTimesBaselineOverDisparity) {
  // Given an ideal rig: f = 500 px, B = 0.1 m
  const CameraModel cam{cv::Matx33d(500, 0, 320, 0, 500, 240, 0, 0, 1), {}};
  const StereoCalibration c =
      make_calibration(cam, cam, cv::Matx33d::eye(), cv::Vec3d(-0.1, 0, 0), cv::Size(640, 480));
  const Triangulator tri = Triangulator::create(c).value();
  // When a centre pair with 25 px disparity is triangulated
  const auto p = tri.point_m(345.0, 320.0, 240.0);
  // Then z = 500 * 0.1 / 25 = 2 m and x = (345 - 320) * 2 / 500 = 0.1 m
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR((*p)[2], 2.0, 1e-9);
  EXPECT_NEAR((*p)[0], 0.1, 1e-9);
  EXPECT_NEAR((*p)[1], 0.0, 1e-9);
  EXPECT_NEAR(*tri.depth_from_disparity_m(25.0), 2.0, 1e-9);
  EXPECT_NEAR(tri.baseline_m(), 0.1, 1e-12);
}

TEST(Triangulator, GivenZeroOrNegativeDisparityWhenTriangulatedThenNone) {
  const Triangulator tri = Triangulator::create(default_synthetic_rig().calibration()).value();
  EXPECT_FALSE(tri.point_m(300.0, 300.0, 240.0).has_value());
  EXPECT_FALSE(tri.point_m(300.0, 310.0, 240.0).has_value());
  EXPECT_FALSE(tri.depth_from_disparity_m(0.0).has_value());
}

TEST(Triangulator, GivenInvalidCalibrationWhenCreatedThenErrorNamesField) {
  StereoCalibration c = default_synthetic_rig().calibration();
  c.p1(0, 0) = 0.0;
  const auto tri = Triangulator::create(c);
  ASSERT_FALSE(tri.has_value());
  EXPECT_EQ(tri.error().rfind("P1:", 0), 0u) << tri.error();
}

TEST(RadiusDepth, GivenDepthWhenExpectedRadiusInvertedThenSameDepth) {
  for (double z : {0.3, 1.0, 2.0, 5.0}) {
    const double r = expected_radius_px(600.0, 0.2, z);
    EXPECT_NEAR(*depth_from_radius_m(600.0, 0.2, r), z, 1e-9);
  }
  // A 0.2 m ball at 2 m under f = 600 px looks ~30 px in radius (small-angle f*R/Z).
  EXPECT_NEAR(expected_radius_px(600.0, 0.2, 2.0), 30.0, 0.1);
  EXPECT_FALSE(depth_from_radius_m(600.0, 0.2, 0.0).has_value());
  EXPECT_FALSE(depth_from_radii_m(600.0, 0.2, 30.0, -1.0).has_value());
  EXPECT_NEAR(*depth_from_radii_m(600.0, 0.2, 28.0, 32.0), *depth_from_radius_m(600, 0.2, 30),
              1e-12);
}

TEST(RadiusDepth, GivenSyntheticBallWhenSeenByBothEyesThenStereoAndSizeDepthsAgree) {
  // Given a 0.2 m ball at 1.5 m in the synthetic rig, with its silhouette radius
  const SyntheticRig rig = default_synthetic_rig();
  const StereoCalibration c = rig.calibration();
  const Rectifier rect = Rectifier::create(c).value();
  const Triangulator tri = Triangulator::create(c).value();
  const cv::Point3d centre(0.05, 0.02, 1.5);
  const cv::Point2d l = rect.rectify_point(Eye::kLeft, rig.project_left(centre));
  const cv::Point2d r = rect.rectify_point(Eye::kRight, rig.project_right(centre));
  const double radius = expected_radius_px(focal_px(c), 0.2, 1.5);
  // When triangulated and sized
  const auto p = tri.point_m(l.x, r.x, 0.5 * (l.y + r.y));
  const auto z_size = depth_from_radii_m(tri.focal_px(), 0.2, radius, radius);
  // Then both depths agree and the size check accepts it, but not a ball twice as big
  ASSERT_TRUE(p.has_value());
  ASSERT_TRUE(z_size.has_value());
  EXPECT_NEAR((*p)[2], *z_size, 0.01);
  const SizeCheckParams params{.ball_diameter_m = 0.2, .max_relative_error = 0.3};
  EXPECT_TRUE(check_size(params, tri.focal_px(), radius, (*p)[2]).consistent);
  const SizeCheck big = check_size(params, tri.focal_px(), 2.0 * radius, (*p)[2]);
  EXPECT_FALSE(big.consistent);
  EXPECT_NEAR(big.relative_error, 1.0, 0.02);
}

TEST(SizeCheckParams, GivenBadValuesWhenValidatedThenFieldNamed) {
  EXPECT_EQ(SizeCheckParams{}.validate(), std::nullopt);
  SizeCheckParams p;
  p.ball_diameter_m = 0.0;
  EXPECT_EQ(p.validate()->rfind("ball_diameter_m", 0), 0u);
  p = {};
  p.max_relative_error = -1.0;
  EXPECT_EQ(p.validate()->rfind("max_relative_error", 0), 0u);
}

}  // namespace
}  // namespace stereoball::stereo

namespace stereoball::stereo {
namespace {

// Given a sphere, when its outline's centre (the tangent circle of the viewing cone, r^2/D in
// front of the sphere's centre) is corrected, then the sphere's centre comes back.
TEST(SphereCentre, GivenOutlineCentreWhenCorrectedThenSphereCentreIsRecovered) {
  const double r = 0.11;
  for (const cv::Vec3d& centre :
       {cv::Vec3d(0.0, 0.0, 1.0), cv::Vec3d(0.3, 0.1, 1.0), cv::Vec3d(-0.5, 0.2, 2.5)}) {
    const double d = cv::norm(centre);
    const cv::Vec3d outline = centre * (1.0 - r * r / (d * d));
    const cv::Vec3d recovered = sphere_centre_from_outline_m(outline, r);
    EXPECT_NEAR(cv::norm(recovered - centre), 0.0, 1e-12);
    EXPECT_GT(cv::norm(centre - outline), 0.004) << "the bias being corrected is real";
  }
  EXPECT_EQ(sphere_centre_from_outline_m(cv::Vec3d(0, 0, 1), 0.0), cv::Vec3d(0, 0, 1));
}

}  // namespace
}  // namespace stereoball::stereo
