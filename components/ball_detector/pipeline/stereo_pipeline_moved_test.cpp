// StereoPipeline on unsynchronised eyes (a motion allowance): a pair that passes only with that
// allowance is withdrawn when its two outlines are not one ball's (check_moved_pair), and a
// ball that really moved between the exposures is still found. Hand-drawn rectified discs.

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <string>

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "stereo/core/sphere_outline.hpp"
#include "stereo/core/synthetic_rig.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

// The synthetic rig, eyes 16.7 ms apart (a 4 m/s ball moves 0.6 of its radius), no floor.
class MovedPair : public ::testing::Test {
 protected:
  void SetUp() override {
    BallDetectorParams p;
    p.floor_tolerance_m = 0.0;
    p.epipolar_skew_ns = 16'700'000;
    params_ = p;
    calib_ = sb::stereo::default_synthetic_rig().calibration();
  }

  // The outline of the ball (params' diameter) centred at centre_m in the left (or right)
  // rectified image.
  cv::Vec3d outline(const StereoPipeline& pipeline, const cv::Vec3d& centre_m, bool right) const {
    const auto cam = right ? pipeline.right_camera() : pipeline.left_camera();
    const double baseline_m = cv::norm(calib_.t);
    const cv::Vec3d in_eye = right ? centre_m - cv::Vec3d(baseline_m, 0, 0) : centre_m;
    const auto o = sb::stereo::sphere_outline(*cam, in_eye, 0.5 * params_.ball_diameter_m);
    return {o->centre_px.x, o->centre_px.y, o->mean_radius_px()};
  }

  // An orange disc (x, y, r) on a grey frame of the calibration's size.
  cv::Mat disc(const cv::Vec3d& c) const {
    cv::Mat m(calib_.image_size, CV_8UC3, cv::Scalar(95, 100, 105));
    cv::circle(m, cv::Point(cvRound(c[0] * 16), cvRound(c[1] * 16)), cvRound(c[2] * 16),
               cv::Scalar(30, 100, 220), cv::FILLED, cv::LINE_AA, 4);
    return m;
  }

  BallDetectorParams params_;
  sb::stereo::StereoCalibration calib_;
};

}  // namespace

TEST_F(MovedPair, GivenOutlinesOfTwoSizesOnRowsApart_ThenNotReportedAtTheirDepth) {
  StereoPipeline pipeline(params_);
  ASSERT_TRUE(pipeline.set_calibration(calib_).ok());
  // Given a ball 1.2 m away whose right outline is drawn 7 % small and whose left one 7 % large,
  // 31 px lower and 8 px right (a fit pulled by hands and the border): rows within the motion
  // allowance, radii differing by more than the ball's depth change in 16.7 ms explains, and
  // a disparity that says 1.06 m
  const cv::Vec3d ball(0.0, 0.0, 1.2);
  const cv::Vec3d l = outline(pipeline, ball, false), r = outline(pipeline, ball, true);
  const cv::Mat left = disc({l[0] + 8.0, l[1] + 31.0, 1.07 * l[2]});
  const cv::Mat right = disc({r[0], r[1], 0.93 * r[2]});
  // When the pair is processed
  const auto det = pipeline.step(left, right, true);
  // Then it is not reported at the depth its disparity gives: the outlines are not one ball's
  EXPECT_EQ(det.status, DetectionStatus::kSizeInconsistent) << det.reason;
  EXPECT_NE(det.reason.find("not one ball's"), std::string::npos) << det.reason;
  EXPECT_NE(det.reason.find("first paired"), std::string::npos) << det.reason;
}

TEST_F(MovedPair, GivenOneBallThatMovedBetweenTheExposures_ThenFound) {
  StereoPipeline pipeline(params_);
  ASSERT_TRUE(pipeline.set_calibration(calib_).ok());
  // Given the same ball whose right exposure came after it dropped 5 cm (19 px of rows at 1.2 m)
  const cv::Vec3d l = outline(pipeline, {0.0, 0.0, 1.2}, false);
  const cv::Vec3d r = outline(pipeline, {0.0, 0.05, 1.2}, true);
  // When the pair is processed
  const auto det = pipeline.step(disc(l), disc(r), true);
  // Then it is found on the left outline, at its depth
  ASSERT_EQ(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_NEAR(det.left.x_px, l[0], 1.5);
  EXPECT_NEAR(det.left.y_px, l[1], 1.5);
  EXPECT_NEAR(det.position_m[2], 1.2, 0.06);
  EXPECT_GT(det.row_residual_px, 10.0);
}
