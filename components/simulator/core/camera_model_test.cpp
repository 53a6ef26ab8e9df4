#include "simulator/core/camera_model.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <vector>

namespace stereoball::simulator {
namespace {

const std::array<double, 5> kDist{-0.12, 0.035, 0.0004, -0.0003, 0.001};

TEST(CameraModel, UndistortInvertsDistortAcrossTheImage) {
  // Given normalized points up to the corners of a 62 degree camera
  for (double x = -0.7; x <= 0.7; x += 0.1) {
    for (double y = -0.55; y <= 0.55; y += 0.1) {
      // When distorted and undistorted again
      const Point2 d = distort_normalized(kDist, {x, y});
      const auto u = undistort_normalized(kDist, d);
      // Then the original point comes back
      ASSERT_TRUE(u.has_value());
      EXPECT_NEAR(u->x, x, 1e-9);
      EXPECT_NEAR(u->y, y, 1e-9);
    }
  }
}

TEST(CameraModel, ProjectRawMatchesOpenCvProjectPoints) {
  // Given intrinsics with distortion and a few camera-frame points
  const Intrinsics k = make_intrinsics({62.0, 1.01, 3.0, -2.0, kDist, 1.0}, 640, 480);
  const std::vector<cv::Point3d> pts{{0.1, 0.2, 1.5}, {-0.6, 0.3, 1.2}, {0.4, -0.35, 0.9}};
  std::vector<cv::Point2d> cv_px;
  const cv::Matx33d km(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  // When projected by OpenCV and by the simulator's model
  cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), km,
                    std::vector<double>(kDist.begin(), kDist.end()), cv_px);
  // Then both agree (the renderer uses exactly OpenCV's distortion model)
  for (size_t i = 0; i < pts.size(); ++i) {
    const Point2 p = project_raw(k, {pts[i].x, pts[i].y, pts[i].z});
    EXPECT_NEAR(p.x, cv_px[i].x, 1e-6);
    EXPECT_NEAR(p.y, cv_px[i].y, 1e-6);
  }
}

TEST(CameraModel, IntrinsicsFollowFieldOfViewAndResolution) {
  // Given the same eye at two resolutions
  const EyeParams eye{60.0, 1.0, 0.0, 0.0, {}, 1.0};
  const Intrinsics a = make_intrinsics(eye, 640, 480);
  const Intrinsics b = make_intrinsics(eye, 352, 288);
  // Then fx scales with the width and the principal point sits at the image centre
  EXPECT_NEAR(a.fx, 320.0 / std::tan(M_PI / 6), 1e-9);
  EXPECT_NEAR(b.fx / a.fx, 352.0 / 640.0, 1e-12);
  EXPECT_DOUBLE_EQ(b.cx, 175.5);
  EXPECT_DOUBLE_EQ(b.cy, 143.5);
}

}  // namespace
}  // namespace stereoball::simulator
