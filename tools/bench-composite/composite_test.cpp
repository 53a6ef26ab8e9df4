// The ball detector's stereo pipeline on real stereo backgrounds with a composited ball
// (OpenCV's chessboard pairs through their calibration, Middlebury Aloe).

#include "composite_run.hpp"

#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "stereo/core/sphere_outline.hpp"
#include "stereo/io/calibration_file.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cstdio>

namespace stereoball::composite {
namespace {

const std::vector<Background>& backgrounds() {
  static const std::vector<Background> all = [] {
    const auto calib = stereo::load_calibration(std::string(SB_SOURCE_DIR) +
                                                "/config/calibration/opencv_samples_stereo.yaml");
    EXPECT_TRUE(calib.ok()) << calib.error();
    auto bgs = load_real_backgrounds(std::string(SB_SHARED_DATA_DIR) + "/opencv-samples", *calib);
    EXPECT_TRUE(bgs.ok()) << bgs.error();
    return bgs.ok() ? bgs.value() : std::vector<Background>{};
  }();
  return all;
}

TEST(Composite, GivenBallWhenCompositedThenOnlyItsOutlineChangesTheImageAndRowsAgree) {
  // Given the first chessboard background and a ball 1.5 m ahead
  ASSERT_EQ(backgrounds().size(), 14u);
  const Background& bg = backgrounds().front();
  const Ball ball{cv::Vec3d(0.05, 0.02, 1.5), 0.11, cv::Scalar(30, 120, 250), "orange"};
  // When composited
  const auto [left, right] = composite(bg, ball);
  // Then each eye changed only inside the sphere's outline (1 px of anti-aliasing), around
  // centres on the same row, disparity f*B/z apart
  const stereo::PinholeCamera cam{bg.focal_px, bg.principal_px};
  for (int eye = 0; eye < 2; ++eye) {
    const cv::Mat& img = eye == 0 ? left : right;
    const cv::Mat& before = eye == 0 ? bg.left : bg.right;
    const auto o =
        stereo::sphere_outline(cam, ball.centre_m - cv::Vec3d(eye * bg.baseline_m, 0, 0), 0.11);
    ASSERT_TRUE(o.has_value());
    cv::Mat diff;
    cv::absdiff(img, before, diff);
    cv::cvtColor(diff, diff, cv::COLOR_BGR2GRAY);
    const cv::Rect changed = cv::boundingRect(diff > 0);
    EXPECT_NEAR(changed.x + 0.5 * changed.width, o->centre_px.x + 0.5, 1.0);
    EXPECT_NEAR(changed.y + 0.5 * changed.height, o->centre_px.y + 0.5, 1.0);
    EXPECT_NEAR(0.5 * changed.height, o->semi_minor_px, 1.5);
  }
}

TEST(Composite, GivenLargeBallAmongChessboardCornersWhenDetectedThenFoundAccurately) {
  // Given the chessboard pair 01 with a blue ball 0.88 m ahead, 65 px across in radius: the
  // board's corners fill every accumulator peak the whole-radius search examines, and before
  // the radius-band search this was a miss ("no circle in the left eye")
  const Background& bg = backgrounds().front();
  const auto balls = place_balls(bg, 3, 0.11, 0.8, 3.0, 17);
  ASSERT_EQ(balls.size(), 3u);
  const Ball& ball = balls[2];
  ASSERT_EQ(ball.colour, "blue");
  ASSERT_NEAR(ball.centre_m[2], 0.88, 0.01);
  ball_detector::StereoPipeline pipeline(composite_params({}, 0.11));
  ASSERT_TRUE(pipeline.set_calibration(rectified_rig_calibration(bg)).ok());
  // When the pipeline runs on it
  const auto [left, right] = composite(bg, ball);
  const auto det = pipeline.step(left, right, true);
  // Then the ball is found, its centre within 0.5 % of its depth
  ASSERT_EQ(det.status, ball_detector::DetectionStatus::kFound) << det.reason;
  EXPECT_LT(cv::norm(det.position_m - ball.centre_m), 0.005 * ball.centre_m[2]);
}

TEST(Composite, GivenWhiteBallOnChessboardWhenSearchedByRadiusThenTheFullWidthBandsFindIt) {
  // Given the chessboard pair 06 with the bench's white ball of seed 99, 1.19 m ahead, 49 px in
  // radius: the whole range misses it among the squares, and so does a radius band on the
  // halved eye (the reason coarse to fine by radius keeps the bands at full width)
  const Background& bg = backgrounds()[5];
  ASSERT_EQ(bg.name, "chessboard06");
  const auto balls = place_balls(bg, 5, 0.11, 0.8, 3.0, 99 + 5);
  ASSERT_EQ(balls.size(), 5u);
  const Ball& ball = balls[3];
  ASSERT_EQ(ball.colour, "white");
  ASSERT_NEAR(ball.centre_m[2], 1.19, 0.01);
  ball_detector::BallDetectorParams params = composite_params({}, 0.11);
  params.coarse_by_radius = true;
  ball_detector::StereoPipeline pipeline(params);
  ASSERT_TRUE(pipeline.set_calibration(rectified_rig_calibration(bg)).ok());
  // When the pipeline searches it coarse to fine by radius (640x480: halved once)
  const auto [left, right] = composite(bg, ball);
  const auto det = pipeline.step(left, right, true);
  // Then the full-width radius bands find it, its centre within 1 % of its depth
  ASSERT_EQ(det.status, ball_detector::DetectionStatus::kFound) << det.reason;
  EXPECT_EQ(det.search, ball_detector::SearchPath::kRadiusBands);
  EXPECT_LT(cv::norm(det.position_m - ball.centre_m), 0.01 * ball.centre_m[2]);
}

TEST(Composite, GivenEveryRealBackgroundWhenBallsCompositedThenMostFoundAndNoFalseDetection) {
  // Given the 14 real backgrounds, two balls each (the bench runs five), and each without one
  SuiteOptions options;
  options.balls_per_background = 2;
  // When the pipeline runs on all of them
  const SuiteResult r = run_suite(backgrounds(), composite_params({}, options.radius_m), options);
  std::printf(
      "composite suite: found %.1f %% of %zu, %d false detections on %d pairs, median "
      "error %.3f %% of depth\n",
      100.0 * r.found_fraction(), r.balls.size(), r.false_detections, r.frames_without_ball,
      100.0 * r.median_error_of_depth());
  // Then no background without a ball gives a detection, and the balls found are where they
  // are. The found rate is below the 95 % target (the misses are outlines with too
  // little contrast in the detector's channel, see the README): this guards today's level.
  EXPECT_EQ(r.false_detections, 0);
  EXPECT_EQ(r.frames_without_ball, 14);
  EXPECT_GE(r.found_fraction(), 0.7);  // 21 of 28 today (before the band search: 17)
  EXPECT_LT(r.median_error_of_depth(), 0.01);
  for (const BallOutcome& b : r.balls) {
    if (b.found) {
      EXPECT_LT(b.error_of_depth, 0.1) << b.background << " " << b.ball.colour;
    }
  }
}

}  // namespace
}  // namespace stereoball::composite
