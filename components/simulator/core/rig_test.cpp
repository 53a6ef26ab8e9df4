#include "simulator/core/rig.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <vector>

#include "simulator/core/ground_truth.hpp"

namespace stereoball::simulator {
namespace {

TEST(StereoRig, ExtrinsicsAreTheBaselineWithTheMountingError) {
  // Given the default rig (right camera mis-rotated and displaced)
  const SimParams p;
  const StereoRig rig(p);
  const auto& c = rig.calibration();
  // Then T points from the right camera back to the left one, about one baseline long
  EXPECT_NEAR(c.t[0], -p.rig.baseline_m, 0.005);
  EXPECT_NEAR(cv::norm(c.t), p.rig.baseline_m, 0.005);
  // And R is a small but non-zero rotation, so rectification is genuinely needed
  cv::Vec3d rvec;
  cv::Rodrigues(c.r, rvec);
  EXPECT_GT(cv::norm(rvec), 0.003);
  EXPECT_LT(cv::norm(rvec), 0.02);
  // And the rectified right projection encodes -f*B
  EXPECT_NEAR(c.p2(0, 3) / c.p2(0, 0), c.t[0], 0.005);
}

TEST(StereoRig, LeftCameraLooksForwardAndDownFromItsMountingHeight) {
  // Given a rig tilted down by 0.3 rad at 0.5 m
  SimParams p;
  p.rig.tilt_rad = 0.3;
  p.rig.height_m = 0.5;
  const StereoRig rig(p);
  const CameraPose& left = rig.pose(Eye::kLeft);
  // Then the optical axis points forward and down, and the left eye sits on the robot's left
  const Vec3d fwd = left.r_robot_from_cam * Vec3d{0, 0, 1};
  EXPECT_NEAR(fwd.x, std::cos(0.3), 1e-12);
  EXPECT_NEAR(fwd.z, -std::sin(0.3), 1e-12);
  EXPECT_NEAR(left.position_m.y, p.rig.baseline_m / 2, 1e-12);
  EXPECT_NEAR(left.position_m.z, 0.5, 1e-12);
}

TEST(StereoRig, GroundTruthAgreesWithOpenCvRectificationOfRawProjections) {
  // Given world points in front of the robot
  const SimParams p;
  const StereoRig rig(p);
  const auto& c = rig.calibration();
  const RobotState robot{0.5, -0.2, 0.3, 0, 0};
  for (const Vec3d& w : {Vec3d{2.0, 0.1, 0.11}, Vec3d{1.6, 0.0, 0.3}, Vec3d{3.0, 0.9, 0.11}}) {
    BallState ball;
    ball.present = true;
    ball.position_m = w;
    // When projected to raw pixels and rectified by OpenCV with the true calibration
    const GroundTruth g = make_ground_truth(rig, robot, ball, 0, 0);
    ASSERT_TRUE(g.ball_visible_left && g.ball_visible_right);
    const Point2 raw_l =
        project_raw(rig.intrinsics(Eye::kLeft), world_to_camera(rig, Eye::kLeft, robot, w));
    const Point2 raw_r =
        project_raw(rig.intrinsics(Eye::kRight), world_to_camera(rig, Eye::kRight, robot, w));
    std::vector<cv::Point2d> rl, rr;
    cv::undistortPoints(std::vector<cv::Point2d>{{raw_l.x, raw_l.y}}, rl, c.k1, c.d1, c.r1, c.p1);
    cv::undistortPoints(std::vector<cv::Point2d>{{raw_r.x, raw_r.y}}, rr, c.k2, c.d2, c.r2, c.p2);
    // Then they land on the ground-truth rectified pixels, on the same row in both eyes
    EXPECT_NEAR(rl[0].x, g.ball_left_px.x, 1e-3);
    EXPECT_NEAR(rl[0].y, g.ball_left_px.y, 1e-3);
    EXPECT_NEAR(rr[0].x, g.ball_right_px.x, 1e-3);
    EXPECT_NEAR(rr[0].y, g.ball_right_px.y, 1e-3);
    EXPECT_NEAR(g.ball_left_px.y, g.ball_right_px.y, 1e-6);
  }
}

}  // namespace
}  // namespace stereoball::simulator
