// Unsynchronised eyes: a pair that needs the motion allowance is withdrawn when the inside of
// its outlines did not move between the exposures as its outlines did (check_interior_motion,
// interior_motion.hpp), and a ball whose inside moved with its outline is still found. Hand-
// drawn rectified balls with a printed inside; interior_offset on shifted texture.

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>
#include <string>

#include "ball_detector/pipeline/interior_motion.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "stereo/core/sphere_outline.hpp"
#include "stereo/core/synthetic_rig.hpp"

namespace sb = stereoball;
using sb::ball_detector::BallDetectorParams;
using sb::ball_detector::Circle;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;

namespace {

// A dark print (dots and two seam strokes) of a ball whose print is centred at (px, py), r px,
// over an orange disc whose outline is (x, y, r): outline and print may sit apart, as when an
// outline fit is pulled off the ball. Grey background; 1/16 px drawing precision.
cv::Mat printed_ball_frame(cv::Size size, const cv::Vec3d& outline, cv::Point2d print) {
  cv::Mat frame(size, CV_8UC3, cv::Scalar(95, 100, 105));
  const auto fixed = [](double v) { return cvRound(v * 16); };
  cv::Mat ball(size, CV_8UC3, cv::Scalar(30, 100, 220));
  const double r = outline[2];
  cv::RNG rng(38);
  for (int i = 0; i < 40; ++i) {
    const cv::Point2d at(print.x + rng.uniform(-0.8, 0.8) * r,
                         print.y + rng.uniform(-0.8, 0.8) * r);
    cv::circle(ball, cv::Point(fixed(at.x), fixed(at.y)), fixed(rng.uniform(0.03, 0.08) * r),
               cv::Scalar(20, 30, 40), cv::FILLED, cv::LINE_AA, 4);
  }
  cv::ellipse(ball, cv::Point(fixed(print.x - 0.9 * r), fixed(print.y)),
              cv::Size(fixed(0.7 * r), fixed(1.1 * r)), 0, 0, 360, cv::Scalar(20, 30, 40), 2,
              cv::LINE_AA, 4);
  cv::line(ball, cv::Point(fixed(print.x - r), fixed(print.y + 0.3 * r)),
           cv::Point(fixed(print.x + r), fixed(print.y - 0.2 * r)), cv::Scalar(20, 30, 40), 2,
           cv::LINE_AA, 4);
  cv::Mat mask(size, CV_8U, cv::Scalar(0));
  cv::circle(mask, cv::Point(fixed(outline[0]), fixed(outline[1])), fixed(r), cv::Scalar(255),
             cv::FILLED, cv::LINE_AA, 4);
  ball.copyTo(frame, mask);
  return frame;
}

// The synthetic rig, eyes 16.7 ms apart (a 4 m/s ball moves 0.6 of its radius), no floor.
class InsideMotion : public ::testing::Test {
 protected:
  void SetUp() override {
    params_.floor_tolerance_m = 0.0;
    params_.epipolar_skew_ns = 16'700'000;
    calib_ = sb::stereo::default_synthetic_rig().calibration();
  }

  // The outline (x, y, r) of the ball centred at centre_m in the left (or right) rectified eye.
  cv::Vec3d outline_of(const StereoPipeline& pipeline, const cv::Vec3d& centre_m,
                       bool right) const {
    const auto cam = right ? pipeline.right_camera() : pipeline.left_camera();
    const cv::Vec3d in_eye = right ? centre_m - cv::Vec3d(cv::norm(calib_.t), 0, 0) : centre_m;
    const auto o = sb::stereo::sphere_outline(*cam, in_eye, 0.5 * params_.ball_diameter_m);
    return {o->centre_px.x, o->centre_px.y, o->mean_radius_px()};
  }

  BallDetectorParams params_;
  sb::stereo::StereoCalibration calib_;
};

}  // namespace

TEST(InteriorOffset, GivenTextureShiftedBetweenTheEyes_ThenTheShiftIsMeasured) {
  // Given a printed ball drawn 3.4 px lower and 20.6 px further left in the right eye
  const cv::Size size(320, 240);
  const cv::Vec3d l(160.0, 120.0, 40.0), r(139.4, 116.6, 40.0);
  const cv::Mat left = printed_ball_frame(size, l, {l[0], l[1]});
  const cv::Mat right = printed_ball_frame(size, r, {r[0], r[1]});
  // When the inside is matched from where the right circle puts it
  const auto o = sb::ball_detector::interior_offset(left, right, {l[0], l[1], l[2], 1.0},
                                                    {r[0], r[1], r[2], 1.0}, 10.0, 10.0);
  // Then the offset is the drawn one, to a fraction of a pixel
  ASSERT_TRUE(o.measured);
  EXPECT_NEAR(o.dx_px, 20.6, 0.5);
  EXPECT_NEAR(o.dy_px, 3.4, 0.5);
  EXPECT_GT(o.match, 0.9);
}

TEST(InteriorOffset, GivenAFlatInside_ThenNothingIsMeasured) {
  // Given an unprinted orange disc in both eyes
  const cv::Size size(320, 240);
  cv::Mat left(size, CV_8UC3, cv::Scalar(95, 100, 105)), right = left.clone();
  cv::circle(left, {160, 120}, 40, cv::Scalar(30, 100, 220), cv::FILLED);
  cv::circle(right, {140, 120}, 40, cv::Scalar(30, 100, 220), cv::FILLED);
  // When its inside is matched
  const auto o = sb::ball_detector::interior_offset(left, right, {160, 120, 40, 1},
                                                    {140, 120, 40, 1}, 10.0, 10.0);
  // Then there is no verdict: nothing inside to match
  EXPECT_FALSE(o.measured);
}

TEST(InteriorOffset, GivenABallCutByTheBottomBorder_ThenItsUpperInsideIsMatched) {
  // Given a printed ball whose centre is 10 px above the bottom border, 6 px lower on the right
  const cv::Size size(320, 240);
  const cv::Vec3d l(160.0, 230.0, 40.0), r(140.0, 224.0, 40.0);
  const cv::Mat left = printed_ball_frame(size, l, {l[0], l[1]});
  const cv::Mat right = printed_ball_frame(size, r, {r[0], r[1]});
  // When matched
  const auto o = sb::ball_detector::interior_offset(left, right, {l[0], l[1], l[2], 1.0},
                                                    {r[0], r[1], r[2], 1.0}, 10.0, 10.0);
  // Then the part in view gives the offset
  ASSERT_TRUE(o.measured);
  EXPECT_NEAR(o.dy_px, 6.0, 0.5);
  // And a ball mostly below the border gives no verdict
  const auto low = sb::ball_detector::interior_offset(left, right, {160.0, 250.0, 40.0, 1.0},
                                                      {140.0, 250.0, 40.0, 1.0}, 10.0, 10.0);
  EXPECT_FALSE(low.measured);
}

TEST_F(InsideMotion, GivenOutlinesPulledOffAnUnmovedBall_ThenThePairIsWithdrawn) {
  StereoPipeline pipeline(params_);
  ASSERT_TRUE(pipeline.set_calibration(calib_).ok());
  // Given a printed ball 1.2 m away seen at the same rows by both eyes (it did not move), whose
  // left outline is drawn 12 px lower and 4 px right of its print (a fit pulled off the ball by
  // hands or by the image border): the radii agree, the rows differ within the motion allowance
  const cv::Vec3d ball(0.0, 0.0, 1.2);
  const cv::Vec3d l = outline_of(pipeline, ball, false), r = outline_of(pipeline, ball, true);
  const cv::Mat left =
      printed_ball_frame(calib_.image_size, {l[0] + 4.0, l[1] + 12.0, l[2]}, {l[0], l[1]});
  const cv::Mat right = printed_ball_frame(calib_.image_size, r, {r[0], r[1]});
  // When the pair is processed
  const auto det = pipeline.step(left, right, true);
  // Then it is not reported: the ball's print says it did not move between the exposures
  EXPECT_EQ(det.status, DetectionStatus::kEpipolarMismatch)
      << det.reason << " at " << det.left.x_px << "," << det.left.y_px;
  EXPECT_NE(det.reason.find("inside of the ball"), std::string::npos) << det.reason;
  // And with the paper's rows (no motion allowance) it is not reported either
  BallDetectorParams paper = params_;
  paper.epipolar_ball_speed_mps = 0.0;
  StereoPipeline strict(paper);
  ASSERT_TRUE(strict.set_calibration(calib_).ok());
  EXPECT_NE(strict.step(left, right, true).status, DetectionStatus::kFound);
}

TEST_F(InsideMotion, GivenAPrintedBallThatMovedBetweenTheExposures_ThenFound) {
  StereoPipeline pipeline(params_);
  ASSERT_TRUE(pipeline.set_calibration(calib_).ok());
  // Given a printed ball whose right exposure came after it dropped 4 cm: outline and print
  // moved together
  const cv::Vec3d l = outline_of(pipeline, {0.0, 0.0, 1.2}, false);
  const cv::Vec3d r = outline_of(pipeline, {0.0, 0.04, 1.2}, true);
  const cv::Mat left = printed_ball_frame(calib_.image_size, l, {l[0], l[1]});
  const cv::Mat right = printed_ball_frame(calib_.image_size, r, {r[0], r[1]});
  // When the pair is processed
  const auto det = pipeline.step(left, right, true);
  // Then it is found on the left outline, at its depth
  ASSERT_EQ(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_NEAR(det.left.x_px, l[0], 1.5);
  EXPECT_NEAR(det.left.y_px, l[1], 1.5);
  EXPECT_NEAR(det.position_m[2], 1.2, 0.06);
  EXPECT_GT(det.row_residual_px, 8.0);
}
