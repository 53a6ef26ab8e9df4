#include "stereo/core/triangulation.hpp"
#include "stereo/core/sphere_outline.hpp"

#include "stereo/core/rectifier.hpp"
#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

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
  EXPECT_NEAR(tri.disparity_for_depth_px(2.0), 25.0, 1e-9);
  EXPECT_NEAR(tri.baseline_m(), 0.1, 1e-12);
}

TEST(Triangulator, GivenZeroOrNegativeDisparityWhenTriangulatedThenNone) {
  const Triangulator tri = Triangulator::create(default_synthetic_rig().calibration()).value();
  EXPECT_FALSE(tri.point_m(300.0, 300.0, 240.0).has_value());
  EXPECT_FALSE(tri.point_m(300.0, 310.0, 240.0).has_value());
  EXPECT_FALSE(tri.depth_from_disparity_m(0.0).has_value());
}

TEST(Triangulator, GivenADepthThenItsDisparityTriangulatesBackToIt) {
  // Principal points that differ between the eyes (as after real rectification) included.
  const Triangulator tri = Triangulator::create(default_synthetic_rig().calibration()).value();
  for (const double depth_m : {0.3, 1.0, 2.5, 7.0}) {
    const auto back = tri.depth_from_disparity_m(tri.disparity_for_depth_px(depth_m));
    ASSERT_TRUE(back.has_value()) << depth_m;
    EXPECT_NEAR(*back, depth_m, 1e-9 * depth_m);
  }
}

TEST(Triangulator, GivenInvalidCalibrationWhenCreatedThenErrorNamesField) {
  StereoCalibration c = default_synthetic_rig().calibration();
  c.p1(0, 0) = 0.0;
  const auto tri = Triangulator::create(c);
  ASSERT_FALSE(tri.ok());
  EXPECT_EQ(tri.error().rfind("P1:", 0), 0u) << tri.error();
}

// Given balls on the optical axis, their outline is the circle of expected_radius_px, and the
// depth comes back from it.
TEST(RadiusDepth, GivenDepthOnTheAxisThenOutlineIsTheExpectedCircleAndDepthComesBack) {
  const PinholeCamera camera{600.0, {320.0, 240.0}};
  for (double z : {0.3, 1.0, 2.0, 5.0}) {
    const double r = expected_radius_px(600.0, 0.2, z);
    const auto o = sphere_outline(camera, {0.0, 0.0, z}, 0.1);
    ASSERT_TRUE(o.has_value());
    EXPECT_NEAR(o->semi_major_px, r, 1e-9);
    EXPECT_NEAR(o->semi_minor_px, r, 1e-9);
    EXPECT_NEAR(sphere_from_outline(camera, camera.principal_px, r)->depth_m(0.1), z, 1e-9);
  }
  // A 0.2 m ball at 2 m under f = 600 px looks ~30 px in radius (small-angle f*R/Z).
  EXPECT_NEAR(expected_radius_px(600.0, 0.2, 2.0), 30.0, 0.1);
  EXPECT_EQ(expected_radius_px(600.0, 0.2, 0.05), 0.0);  // camera inside the ball
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
  const PinholeCamera camera{tri.focal_px(), tri.principal_left_px()};
  const double radius = sphere_outline(camera, centre, 0.1)->mean_radius_px();
  // When triangulated and sized
  const auto p = tri.point_m(l.x, r.x, 0.5 * (l.y + r.y));
  const auto view = sphere_from_outline(camera, l, radius);
  // Then both depths agree and the size check accepts it, but not a ball twice as big
  ASSERT_TRUE(p.has_value());
  ASSERT_TRUE(view.has_value());
  EXPECT_NEAR((*p)[2], view->depth_m(0.1), 0.01);
  const SizeCheckParams params{.ball_diameter_m = 0.2, .max_relative_error = 0.3};
  const double expected = sphere_outline(camera, *p, 0.1)->mean_radius_px();
  EXPECT_TRUE(check_size_against(params, radius, expected).consistent);
  EXPECT_FALSE(check_size_against(params, radius, 0.0).consistent);
  const SizeCheck big = check_size_against(params, 2.0 * radius, expected);
  EXPECT_FALSE(big.consistent);
  EXPECT_NEAR(big.relative_error, 1.0, 0.02);
}

TEST(SizeCheckParams, GivenBadValuesWhenValidatedThenFieldNamed) {
  EXPECT_TRUE(SizeCheckParams{}.validate().ok());
  SizeCheckParams p;
  p.ball_diameter_m = 0.0;
  EXPECT_EQ(p.validate().error().rfind("ball_diameter_m", 0), 0u);
  p = {};
  p.max_relative_error = -1.0;
  EXPECT_EQ(p.validate().error().rfind("max_relative_error", 0), 0u);
}

}  // namespace
}  // namespace stereoball::stereo

namespace stereoball::stereo {
namespace {

// Projects the silhouette of a sphere (centre c, radius r, camera at the origin looking along
// +z, focal f, principal point pp): points of the sphere where the viewing ray is tangent.
std::vector<cv::Point2f> silhouette_px(const cv::Vec3d& c, double r, double f, cv::Point2d pp) {
  const double d = cv::norm(c);
  const cv::Vec3d axis = c / d;
  // The tangent points form a circle of radius r*sqrt(d^2-r^2)/d around axis*(d - r^2/d).
  const cv::Vec3d centre = axis * (d - r * r / d);
  const double rho = r * std::sqrt(d * d - r * r) / d;
  const cv::Vec3d e1 = cv::normalize(axis.cross(cv::Vec3d(0, 1, 0)));
  const cv::Vec3d e2 = axis.cross(e1);
  std::vector<cv::Point2f> out;
  for (int i = 0; i < 720; ++i) {
    const double a = i * CV_PI / 360.0;
    const cv::Vec3d p = centre + rho * (std::cos(a) * e1 + std::sin(a) * e2);
    out.emplace_back(static_cast<float>(pp.x + f * p[0] / p[2]),
                     static_cast<float>(pp.y + f * p[1] / p[2]));
  }
  return out;
}

// Given spheres on and off the axis, when the centre of their exact image outline (an ellipse,
// fitted by OpenCV) is corrected, then it lands on the projection of the sphere's centre.
TEST(SphereCentre, GivenOutlineEllipseCentreWhenCorrectedThenCentreProjectionIsRecovered) {
  const double f = 530.0, r = 0.11;
  const cv::Point2d pp(318.0, 242.0);
  for (const cv::Vec3d& c : {cv::Vec3d(0.0, 0.0, 1.0), cv::Vec3d(0.35, 0.1, 1.0),
                             cv::Vec3d(-0.5, 0.25, 1.2), cv::Vec3d(0.9, -0.3, 2.5)}) {
    const cv::Point2d truth(pp.x + f * c[0] / c[2], pp.y + f * c[1] / c[2]);
    const cv::RotatedRect ellipse = cv::fitEllipse(silhouette_px(c, r, f, pp));
    const cv::Point2d outline_centre(ellipse.center.x, ellipse.center.y);
    const cv::Point2d fixed = sphere_centre_image_px(outline_centre, pp, f, r / cv::norm(c));
    EXPECT_LT(cv::norm(fixed - truth), 0.01) << c;
    if (c[0] != 0.0) {
      EXPECT_GT(cv::norm(outline_centre - truth), 0.3) << "the bias is real";
    }
  }
  EXPECT_EQ(sphere_centre_image_px({400, 300}, pp, f, 0.0), cv::Point2d(400, 300));
}

// Given spheres on and off the axis, near and far, when their exact silhouettes are fitted with
// an ellipse by OpenCV, then sphere_outline predicts its centre, both semi-axes and the
// direction of the major axis.
TEST(SphereOutline, GivenExactSilhouettesThenCentreAxesAndDirectionMatchAFittedEllipse) {
  const PinholeCamera camera{530.0, {318.0, 242.0}};
  const double r = 0.11;
  for (const cv::Vec3d& c :
       {cv::Vec3d(0.0, 0.0, 1.0), cv::Vec3d(0.35, 0.1, 1.0), cv::Vec3d(-0.5, 0.25, 1.2),
        cv::Vec3d(0.9, -0.3, 2.5), cv::Vec3d(-0.3, 0.2, 0.45), cv::Vec3d(0.6, 0.45, 0.9)}) {
    const auto o = sphere_outline(camera, c, r);
    ASSERT_TRUE(o.has_value()) << c;
    const cv::RotatedRect e =
        cv::fitEllipse(silhouette_px(c, r, camera.focal_px, camera.principal_px));
    const double fit_major = 0.5 * std::max(e.size.width, e.size.height);
    const double fit_minor = 0.5 * std::min(e.size.width, e.size.height);
    EXPECT_LT(cv::norm(o->centre_px - cv::Point2d(e.center.x, e.center.y)), 0.01) << c;
    EXPECT_NEAR(o->semi_major_px, fit_major, 0.01) << c;
    EXPECT_NEAR(o->semi_minor_px, fit_minor, 0.01) << c;
    if (fit_major - fit_minor > 0.5) {
      // OpenCV's angle is that of the width axis; the major axis is either it or across it.
      const double a = e.angle * CV_PI / 180.0;
      const cv::Point2d width_axis(std::cos(a), std::sin(a));
      const cv::Point2d fit_axis =
          e.size.width >= e.size.height ? width_axis : cv::Point2d(-width_axis.y, width_axis.x);
      EXPECT_GT(std::abs(fit_axis.dot(o->major_axis)), 0.9999) << c;
    }
  }
}

// Given outlines of spheres anywhere in a wide view, when the sphere is recovered from the
// outline's centre and mean radius, then its direction, size and depth come back exactly.
TEST(SphereOutline, GivenAnOutlineThenSphereFromOutlineInvertsIt) {
  const PinholeCamera camera{400.0, {320.0, 240.0}};
  const double r = 0.11;
  int checked = 0;
  for (double x = -1.5; x <= 1.5; x += 0.25)
    for (double y = -1.0; y <= 1.0; y += 0.5)
      for (double z : {0.3, 0.6, 1.0, 2.0, 5.0}) {
        const cv::Vec3d c(x, y, z);
        const auto o = sphere_outline(camera, c, r);
        if (!o) continue;
        const auto v = sphere_from_outline(camera, o->centre_px, o->mean_radius_px());
        ASSERT_TRUE(v.has_value()) << c;
        EXPECT_NEAR(v->depth_m(r), z, 1e-9 * z) << c;
        const double t = std::hypot(x, y) / z;
        EXPECT_NEAR(v->tan_off_axis, t, 1e-9 * (1.0 + t)) << c;
        EXPECT_NEAR(v->axis_ratio, o->semi_major_px / o->semi_minor_px, 1e-9) << c;
        if (x != 0.0 || y != 0.0) {
          EXPECT_NEAR(v->major_axis.dot(o->major_axis), 1.0, 1e-12);
        }
        ++checked;
      }
  EXPECT_GT(checked, 300);
}

TEST(SphereOutline, GivenImpossibleInputThenNoOutlineAndNoSphere) {
  const PinholeCamera camera{400.0, {320.0, 240.0}};
  EXPECT_FALSE(sphere_outline(camera, {0.0, 0.0, 0.05}, 0.11));  // camera inside the ball
  EXPECT_FALSE(sphere_outline(camera, {0.0, 0.0, -1.0}, 0.11));  // behind the camera
  EXPECT_FALSE(sphere_outline(camera, {3.0, 0.0, 0.01}, 0.11));  // reaches 90 degrees
  EXPECT_FALSE(sphere_outline(camera, {0.0, 0.0, 1.0}, 0.0));
  EXPECT_FALSE(sphere_outline(PinholeCamera{}, {0.0, 0.0, 1.0}, 0.11));
  EXPECT_FALSE(sphere_from_outline(camera, {320.0, 240.0}, 0.0));
  EXPECT_FALSE(sphere_from_outline(camera, {NAN, 240.0}, 10.0));
  EXPECT_FALSE(sphere_from_outline(PinholeCamera{}, {320.0, 240.0}, 10.0));
}

// Given an ideal rectified rig and a ball off to the side, when the centres of the two exact
// outlines are triangulated with sphere_centre_m, then the ball's centre comes back to 0.1 mm,
// while plain triangulation of the outline centres is millimetres off.
TEST(SphereCentre, GivenBothOutlinesWhenTriangulatedThenSphereCentreIsRecovered) {
  const double f = 500.0, b = 0.12, r = 0.11;
  const cv::Point2d pp(320.0, 240.0);
  const CameraModel cam{cv::Matx33d(f, 0, pp.x, 0, f, pp.y, 0, 0, 1), {}};
  const Triangulator tri =
      Triangulator::create(
          make_calibration(cam, cam, cv::Matx33d::eye(), cv::Vec3d(-b, 0, 0), cv::Size(640, 480)))
          .value();
  for (const cv::Vec3d& c :
       {cv::Vec3d(0.06, 0.0, 0.8), cv::Vec3d(0.4, 0.15, 1.0), cv::Vec3d(-0.6, 0.1, 2.0)}) {
    auto centre_of = [&](const cv::Vec3d& in_eye) {
      const cv::RotatedRect e = cv::fitEllipse(silhouette_px(in_eye, r, f, pp));
      return cv::Point2d(e.center.x, e.center.y);
    };
    const cv::Point2d left = centre_of(c);
    const cv::Point2d right = centre_of(c - cv::Vec3d(b, 0, 0));
    const auto fixed = tri.sphere_centre_m(left, right, r);
    ASSERT_TRUE(fixed.has_value());
    EXPECT_LT(cv::norm(*fixed - c), 1e-4) << c << " got " << *fixed;
    const auto plain = tri.point_m(left.x, right.x, 0.5 * (left.y + right.y));
    EXPECT_GT(cv::norm(*plain - c), 2e-3) << "the bias being corrected is real";
  }
}

}  // namespace
}  // namespace stereoball::stereo
