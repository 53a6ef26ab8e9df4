// StereoPipeline on frames rendered by the simulator (raw, distorted, noisy) with ground truth.

#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "simulator/core/ball_scene.hpp"
#include "stereo/core/rectifier.hpp"

namespace sb = stereoball;
using sb::ball_detector::DetectionStatus;
using sb::ball_detector::StereoPipeline;
using sb::simulator::SimBallSetup;

namespace {

struct Rendered {
  sb::simulator::SimFrame frame;
  sb::stereo::StereoCalibration calib;
};

// A one-colour ball in a plain room: the scenes the current P2P core finds reliably.
SimBallSetup plain_scene(double x_m, double y_m) {
  SimBallSetup s;
  s.ball_x_m = x_m;
  s.ball_y_m = y_m;
  s.clutter = false;
  s.plain_room = true;
  s.uniform_ball = true;
  return s;
}

Rendered render(const SimBallSetup& setup) {
  const auto params = sb::simulator::default_sim_params();
  const auto scenario = sb::simulator::make_sim_scenario(setup);
  EXPECT_TRUE(sb::simulator::Simulator::check(params, scenario).ok());
  sb::simulator::Simulator sim(params, scenario);
  return {sim.step(std::nullopt, 0), sim.calibration()};
}

double norm3(const cv::Vec3d& v) {
  return std::sqrt(v.dot(v));
}

cv::Vec3d truth_m(const sb::simulator::GroundTruth& t) {
  return {t.ball_camera_m.x, t.ball_camera_m.y, t.ball_camera_m.z};
}

}  // namespace

TEST(StereoPipeline, GivenNoCalibration_WhenStepping_ThenNoCalibrationStatus) {
  StereoPipeline pipeline({});
  const cv::Mat img(480, 640, CV_8UC3, cv::Scalar::all(100));
  const auto det = pipeline.step(img, img, false);
  EXPECT_EQ(det.status, DetectionStatus::kNoCalibration);
  EXPECT_FALSE(det.reason.empty());
  EXPECT_FALSE(pipeline.has_calibration());
}

TEST(StereoPipeline, GivenInvalidCalibration_ThenRejectedAndStillUncalibrated) {
  StereoPipeline pipeline({});
  sb::stereo::StereoCalibration bad;  // zero size, identity matrices
  EXPECT_FALSE(pipeline.set_calibration(bad).ok());
  EXPECT_FALSE(pipeline.has_calibration());
}

TEST(StereoPipeline, GivenCalibrationOfSwappedCameras_ThenRejectedSayingHowToFix) {
  // Given a working calibration and the same rig with its cameras exchanged
  const Rendered r = render(plain_scene(1.5, 0.0));
  StereoPipeline pipeline({});
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  // When the swapped one arrives, Then it is rejected with the reason and the fix, and the
  // previous calibration stays in use
  const auto problem = pipeline.set_calibration(sb::stereo::swapped_cameras(r.calib));
  ASSERT_FALSE(problem.ok());
  EXPECT_NE(problem.error().find("negative baseline"), std::string::npos) << problem.error();
  EXPECT_NE(problem.error().find("left_device and right_device"), std::string::npos)
      << problem.error();
  EXPECT_GT(pipeline.rectifier()->calibration().p2(0, 3) * r.calib.p2(0, 3), 0.0);
  EXPECT_EQ(pipeline.step(r.frame.left, r.frame.right, false).status, DetectionStatus::kFound);
}

TEST(StereoPipeline, GivenWrongSizeOrType_ThenBadFrameNamingTheProblem) {
  const Rendered r = render(plain_scene(1.5, 0.0));
  StereoPipeline pipeline({});
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  const cv::Mat small(240, 320, CV_8UC3, cv::Scalar::all(90));
  auto det = pipeline.step(small, small, false);
  EXPECT_EQ(det.status, DetectionStatus::kBadFrame);
  EXPECT_NE(det.reason.find("320x240"), std::string::npos) << det.reason;
  const cv::Mat floats(480, 640, CV_32FC1, cv::Scalar::all(0));
  det = pipeline.step(floats, floats, false);
  EXPECT_EQ(det.status, DetectionStatus::kBadFrame);
  EXPECT_FALSE(det.reason.empty());
  // The next good frame is answered normally.
  det = pipeline.step(r.frame.left, r.frame.right, false);
  EXPECT_EQ(det.status, DetectionStatus::kFound) << det.reason;
}

class RenderedBall : public ::testing::TestWithParam<SimBallSetup> {};

// Given a still ball rendered by the simulator at a known place,
// when the pipeline processes the raw (distorted, noisy) pair with the true calibration,
// then the left centre is within 1 px of the rectified ground truth (right within 2 px), the
// 3D position within 2 %
// of the distance, and the patch shows the orange ball.
TEST_P(RenderedBall, FindsTheBallWithinOnePixel) {
  const Rendered r = render(GetParam());
  const auto& truth = r.frame.truth;
  ASSERT_TRUE(truth.ball_visible_left && truth.ball_visible_right);
  StereoPipeline pipeline({});
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  const auto det = pipeline.step(r.frame.left, r.frame.right, false);
  ASSERT_EQ(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_NEAR(det.left.x_px, truth.ball_left_px.x, 1.0);
  EXPECT_NEAR(det.left.y_px, truth.ball_left_px.y, 1.0);
  // The right eye (lower gain, shadow side) is detected less precisely by the current core.
  EXPECT_NEAR(det.right.x_px, truth.ball_right_px.x, 2.0);
  EXPECT_NEAR(det.right.y_px, truth.ball_right_px.y, 2.0);
  EXPECT_LE(det.row_residual_px, 2.0);
  const cv::Vec3d gt = truth_m(truth);
  EXPECT_LT(norm3(det.position_m - gt), 0.02 * norm3(gt))
      << "got " << det.position_m << " truth " << gt;
  EXPECT_NEAR(det.depth_from_size_m, gt[2], 0.15 * gt[2]);
  EXPECT_GE(det.candidates_left, 1);
  EXPECT_GE(det.candidates_right, 1);
  ASSERT_TRUE(det.patch_valid);
  const int centre = (10 * 21 + 10) * 3;  // R, G, B of the middle pixel
  EXPECT_GT(det.patch_rgb[centre + 0], det.patch_rgb[centre + 1]);
  EXPECT_GT(det.patch_rgb[centre + 1], det.patch_rgb[centre + 2]);
}

INSTANTIATE_TEST_SUITE_P(Positions, RenderedBall,
                         ::testing::Values(plain_scene(1.5, 0.0), plain_scene(1.0, 0.1),
                                           plain_scene(1.2, 0.25)));

// Given the right eye searched over the whole image instead of the partner boxes,
// then the same pair is found (the boxes only save time).
TEST(StereoPipeline, GivenFullRightSearch_ThenSameResultAsPartnerBoxes) {
  const Rendered r = render(plain_scene(1.5, 0.0));
  sb::ball_detector::BallDetectorParams box_params;
  sb::ball_detector::BallDetectorParams full_params;
  full_params.right_eye_partner_boxes = false;
  StereoPipeline boxes(box_params);
  StereoPipeline full(full_params);
  ASSERT_TRUE(boxes.set_calibration(r.calib).ok());
  ASSERT_TRUE(full.set_calibration(r.calib).ok());
  const auto a = boxes.step(r.frame.left, r.frame.right, false);
  const auto b = full.step(r.frame.left, r.frame.right, false);
  ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
  ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
  EXPECT_NEAR(a.right.x_px, b.right.x_px, 0.25);
  EXPECT_NEAR(a.right.y_px, b.right.y_px, 0.25);
  EXPECT_NEAR(a.position_m[2], b.position_m[2], 0.01);
}

// Given the same pair already rectified by the source,
// when processed with rectified = true,
// then the result matches the raw path (the LUT is skipped, not applied twice).
TEST(StereoPipeline, GivenPreRectifiedFrames_ThenSameBallAsRawPath) {
  const Rendered r = render(plain_scene(1.5, 0.0));
  auto rectifier = sb::stereo::Rectifier::create(r.calib);
  ASSERT_TRUE(rectifier.ok());
  cv::Mat left, right;
  ASSERT_TRUE(rectifier->rectify(r.frame.left, r.frame.right, left, right).ok());
  StereoPipeline pipeline({});
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  const auto det = pipeline.step(left, right, true);
  ASSERT_EQ(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_NEAR(det.left.x_px, r.frame.truth.ball_left_px.x, 1.0);
  EXPECT_NEAR(det.left.y_px, r.frame.truth.ball_left_px.y, 1.0);
  EXPECT_TRUE(det.patch_valid);
}

// Given a scene without a ball (plain room),
// then no ball is reported and the reason says why.
TEST(StereoPipeline, GivenNoBall_ThenNotFound) {
  SimBallSetup s = plain_scene(1.5, 0.0);
  s.ball_y_m = 2.5;  // far to the left, outside the field of view
  const Rendered r = render(s);
  ASSERT_FALSE(r.frame.truth.ball_visible_left);
  StereoPipeline pipeline({});
  ASSERT_TRUE(pipeline.set_calibration(r.calib).ok());
  const auto det = pipeline.step(r.frame.left, r.frame.right, false);
  EXPECT_NE(det.status, DetectionStatus::kFound) << det.reason;
  EXPECT_FALSE(det.reason.empty());
  EXPECT_FALSE(det.patch_valid);
}

TEST(ChannelImages, GivenColours_ThenSaturationIsMaxMinusMinAndValueIsMax) {
  cv::Mat bgr(1, 3, CV_8UC3);
  bgr.at<cv::Vec3b>(0, 0) = {20, 110, 230};
  bgr.at<cv::Vec3b>(0, 1) = {128, 128, 128};
  bgr.at<cv::Vec3b>(0, 2) = {255, 0, 40};
  cv::Mat s;
  sb::ball_detector::saturation(bgr, s);
  EXPECT_EQ(s.at<uint8_t>(0, 0), 210);
  EXPECT_EQ(s.at<uint8_t>(0, 1), 0);
  EXPECT_EQ(s.at<uint8_t>(0, 2), 255);
  sb::ball_detector::value(bgr, s);
  EXPECT_EQ(s.at<uint8_t>(0, 0), 230);
  EXPECT_EQ(s.at<uint8_t>(0, 1), 128);
  EXPECT_EQ(s.at<uint8_t>(0, 2), 255);
}

// Given a BGR image with distinct pixel values, when the patch is cut at the top-left corner,
// then it is R,G,B row-major and outside pixels repeat the border.
TEST(ExtractPatch, GivenCornerCentre_ThenClampedAtBordersInRgbOrder) {
  cv::Mat bgr(30, 40, CV_8UC3);
  for (int y = 0; y < bgr.rows; ++y)
    for (int x = 0; x < bgr.cols; ++x)
      bgr.at<cv::Vec3b>(y, x) = {static_cast<uint8_t>(x), static_cast<uint8_t>(y), 200};
  std::array<uint8_t, sb::ball_detector::kPatchBytes> patch{};
  sb::ball_detector::extract_patch(bgr, 0.2, 1.4, patch);  // nearest pixel (0, 1)
  auto at = [&](int r, int c, int ch) { return patch[static_cast<size_t>((r * 21 + c) * 3 + ch)]; };
  EXPECT_EQ(at(10, 10, 0), 200);  // R
  EXPECT_EQ(at(10, 10, 1), 1);    // G = y
  EXPECT_EQ(at(10, 10, 2), 0);    // B = x
  EXPECT_EQ(at(0, 0, 1), 0);      // row 1 - 10 clamped to 0
  EXPECT_EQ(at(0, 0, 2), 0);      // column -10 clamped to 0
  EXPECT_EQ(at(20, 20, 1), 11);   // row 11
  EXPECT_EQ(at(20, 20, 2), 10);   // column 10
  cv::Mat grey(30, 40, CV_8UC1, cv::Scalar(77));
  sb::ball_detector::extract_patch(grey, 39.0, 29.0, patch);
  EXPECT_EQ(at(20, 20, 0), 77);
  EXPECT_EQ(at(20, 20, 1), 77);
  EXPECT_EQ(at(20, 20, 2), 77);
}

// Given a prior at the ball, when the pipeline searches only near it, then it finds the same
// pair as the whole-frame search; with a prior far from the ball it still finds the ball
// (whole frame after the prior's box came up empty).
TEST(StereoPipeline, GivenPriorNearOrFarFromTheBall_ThenSameBallAsWithout) {
  const Rendered r = render(plain_scene(1.2, 0.1));
  StereoPipeline plain({});
  StereoPipeline with_prior({});
  ASSERT_TRUE(plain.set_calibration(r.calib).ok());
  ASSERT_TRUE(with_prior.set_calibration(r.calib).ok());
  const auto a = plain.step(r.frame.left, r.frame.right, false);
  ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
  // The first frame has no thresholds cached yet: whole frame.
  (void)with_prior.step(r.frame.left, r.frame.right, false);
  const sb::ball_detector::PositionPrior near{a.position_m + cv::Vec3d(0.05, 0.0, 0.05), 0.3};
  const auto b = with_prior.step(r.frame.left, r.frame.right, false, near);
  ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
  EXPECT_NEAR(b.left.x_px, a.left.x_px, 0.05);
  EXPECT_NEAR(b.left.y_px, a.left.y_px, 0.05);
  EXPECT_NEAR(b.position_m[2], a.position_m[2], 0.002);
  // Only the box was searched: the rest of the rectified left image is empty.
  EXPECT_EQ(with_prior.rectified_left().at<uchar>(5, 5), 0);
  const sb::ball_detector::PositionPrior far{cv::Vec3d(-1.0, 0.0, 3.0), 0.3};
  const auto c = with_prior.step(r.frame.left, r.frame.right, false, far);
  ASSERT_EQ(c.status, DetectionStatus::kFound) << c.reason;
  EXPECT_NEAR(c.left.x_px, a.left.x_px, 0.05);
}

namespace {

// The config's radius range (config/ball_detector.yaml): balls up to 0.4 m away.
sb::ball_detector::BallDetectorParams close_ball_params() {
  sb::ball_detector::BallDetectorParams p;
  p.p2p.min_radius_px = 4.0;
  p.p2p.max_radius_px = 250.0;
  p.p2p.min_separation_px = 10.0;
  return p;
}

// A textured ball x_m ahead on the floor and y_m to the left, cut by the bottom border.
Rendered render_close_ball(double x_m, double y_m) {
  SimBallSetup s = plain_scene(x_m, y_m);
  s.plain_room = false;
  s.uniform_ball = false;
  return render(s);
}

// Steps once without a prior (the window search needs a whole frame's thresholds), then with
// a prior at the true position.
sb::ball_detector::StereoDetection step_with_prior(StereoPipeline& pipe, const Rendered& r) {
  EXPECT_TRUE(pipe.set_calibration(r.calib).ok());
  (void)pipe.step(r.frame.left, r.frame.right, false);
  const sb::ball_detector::PositionPrior prior{truth_m(r.frame.truth), 0.3};
  return pipe.step(r.frame.left, r.frame.right, false, prior);
}

}  // namespace

// Given a ball 0.38 m away whose lower part lies below both images and, in the right eye, its
// left side beyond the left border: the right eye holds too little of it for a circle of its
// own. Near a prior (the tracker follows it) the right partner is found along the left
// circle's epipolar line as the outline its ball makes there (predicted_partner: 20 % of it in
// view suffices), with the position within 2 % of the distance. On the whole frame, where a
// new track would start, a predicted outline needs the detector's own border rule (half in
// view): a chance circle in dense texture at the left border pairs that way with almost any
// disparity, so no pair; with a lenient p2p.min_inside_fraction the whole frame pairs it too.
// Without the search no pair is found on the whole frame.
TEST(StereoPipeline, GivenABallCutByTheBorder_ThenPredictedPartnerFindsItNearThePrior) {
  const Rendered r = render_close_ball(0.44, 0.10);
  ASSERT_TRUE(r.frame.truth.ball_visible_left && r.frame.truth.ball_visible_right);
  const cv::Vec3d truth = truth_m(r.frame.truth);
  StereoPipeline pipe(close_ball_params());
  ASSERT_TRUE(pipe.set_calibration(r.calib).ok());
  const auto whole = pipe.step(r.frame.left, r.frame.right, false);
  EXPECT_NE(whole.status, DetectionStatus::kFound) << whole.reason;
  const auto near = step_with_prior(pipe, r);
  ASSERT_EQ(near.status, DetectionStatus::kFound) << near.reason;
  EXPECT_LT(norm3(near.position_m - truth), 0.02 * truth[2]);
  // Half the epipolar tolerance (2 px): the left circle of a ball this cut is refined on its
  // upper arc alone (0.71 px with the node's k = 3, 5; below 0.5 px with k = 5 alone).
  EXPECT_LT(near.row_residual_px, 1.0);

  auto lenient = close_ball_params();
  lenient.p2p.refine_params.min_inside_fraction = 0.2;
  StereoPipeline lenient_pipe(lenient);
  ASSERT_TRUE(lenient_pipe.set_calibration(r.calib).ok());
  const auto lenient_whole = lenient_pipe.step(r.frame.left, r.frame.right, false);
  ASSERT_EQ(lenient_whole.status, DetectionStatus::kFound) << lenient_whole.reason;
  EXPECT_LT(norm3(lenient_whole.position_m - truth), 0.02 * truth[2]);

  auto off = close_ball_params();
  off.predicted_partner = false;
  StereoPipeline without(off);
  ASSERT_TRUE(without.set_calibration(r.calib).ok());
  const auto e = without.step(r.frame.left, r.frame.right, false);
  EXPECT_NE(e.status, DetectionStatus::kFound) << e.reason;
  // Near the prior (radii known, the border rule relaxed) the right eye's own cut circle,
  // polished (PixelToPixelParams::polish), can now pair without the search: then it must be
  // the ball.
  const auto f = step_with_prior(without, r);
  if (f.status == DetectionStatus::kFound) {
    EXPECT_LT(norm3(f.position_m - truth), 0.02 * truth[2]);
  }
}

// Given a ball 0.29 m away whose centre projects below the image (most of it out of view), then
// with the prior the left circle is found with its centre outside the image (the accumulator is
// padded there) and the position is right.
TEST(StereoPipeline, GivenPriorOnABallCentredBelowTheImage_ThenFoundWithItsCentreOutside) {
  const Rendered r = render_close_ball(0.36, 0.0);
  ASSERT_GT(r.frame.truth.ball_left_px.y, 480.0);
  StereoPipeline pipe(close_ball_params());
  const auto d = step_with_prior(pipe, r);
  ASSERT_EQ(d.status, DetectionStatus::kFound) << d.reason;
  EXPECT_GT(d.left.y_px, 479.0);
  const cv::Vec3d truth = truth_m(r.frame.truth);
  EXPECT_LT(norm3(d.position_m - truth), 0.02 * truth[2]);
}

// Given a ball only the prior's window search finds (centred below the image: the whole-frame
// search has no accumulator cell for its centre), then the periodic whole-frame search does not
// lose it: every frame of a run longer than kFullSearchEveryFrames is found.
TEST(StereoPipeline, GivenABallOnlyTheWindowFinds_ThenThePeriodicWholeFrameSearchKeepsIt) {
  const Rendered r = render_close_ball(0.36, 0.0);
  StereoPipeline pipe(close_ball_params());
  ASSERT_TRUE(pipe.set_calibration(r.calib).ok());
  const auto whole = pipe.step(r.frame.left, r.frame.right, false);
  ASSERT_NE(whole.status, DetectionStatus::kFound) << whole.reason;
  const sb::ball_detector::PositionPrior prior{truth_m(r.frame.truth), 0.3};
  for (int i = 0; i < 2 * sb::ball_detector::kFullSearchEveryFrames + 2; ++i) {
    const auto d = pipe.step(r.frame.left, r.frame.right, false, prior);
    EXPECT_EQ(d.status, DetectionStatus::kFound) << "frame " << i << ": " << d.reason;
  }
}

// Given a ball found where the prior says, frame after frame: the whole frame is not searched
// for the answer, and every kFullSearchEveryFrames frames a threshold refresh falls due, which
// finish_frame does once (after the answer) and then has nothing to do; a frame that does not
// fit the calibration is refused; without finish_frame the next step does it and still finds
// the ball.
TEST(StereoPipeline, GivenTheBallFoundAtThePrior_ThenTheThresholdRefreshWaitsForFinishFrame) {
  const Rendered r = render(plain_scene(1.2, 0.1));
  StereoPipeline pipe({});
  ASSERT_TRUE(pipe.set_calibration(r.calib).ok());
  const auto a = pipe.step(r.frame.left, r.frame.right, false);
  ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
  EXPECT_FALSE(pipe.finish_frame(r.frame.left, false));  // the whole frame just measured them
  const sb::ball_detector::PositionPrior prior{a.position_m, 0.3};
  int refreshes = 0;
  for (int i = 0; i < 2 * sb::ball_detector::kFullSearchEveryFrames + 1; ++i) {
    const auto d = pipe.step(r.frame.left, r.frame.right, false, prior);
    ASSERT_EQ(d.status, DetectionStatus::kFound) << "frame " << i << ": " << d.reason;
    EXPECT_NEAR(d.left.x_px, a.left.x_px, 0.05);
    // Only the prior's box was searched for the answer, also on the frames a refresh fell due.
    EXPECT_EQ(pipe.rectified_left().at<uchar>(5, 5), 0) << "frame " << i;
    if (pipe.finish_frame(cv::Mat(), false)) ADD_FAILURE() << "an empty frame was used";
    if (pipe.finish_frame(r.frame.left, false)) {
      ++refreshes;
      EXPECT_FALSE(pipe.finish_frame(r.frame.left, false)) << "refreshed twice";
    }
  }
  EXPECT_EQ(refreshes, 2);
  // Skipping finish_frame: the next frame refreshes first and finds the ball as before.
  for (int i = 0; i < sb::ball_detector::kFullSearchEveryFrames + 2; ++i) {
    const auto d = pipe.step(r.frame.left, r.frame.right, false, prior);
    ASSERT_EQ(d.status, DetectionStatus::kFound) << "frame " << i << ": " << d.reason;
  }
}

// Given a prior a few millimetres off the ball (a tracker's prediction), then the outlines it
// predicts, refined in each eye without voting, answer with the pair voting in the prior's box
// finds (track_prior.seeded off) to within 0.3 px and 3 mm; given a prior 8 cm off sideways
// (within the gate, beyond the seeds' reach), the box is searched by voting and finds the ball.
TEST(StereoPipeline, GivenAPriorThenItsExpectedOutlinesAnswerWhereTheyHoldAndVotingWhereNot) {
  SimBallSetup textured = plain_scene(1.2, 0.1);
  textured.plain_room = false;
  textured.uniform_ball = false;
  for (const SimBallSetup& setup : {plain_scene(1.2, 0.1), textured}) {
    const Rendered r = render(setup);
    const cv::Vec3d truth = truth_m(r.frame.truth);
    sb::ball_detector::BallDetectorParams voting_params;
    voting_params.prior_seeded = false;
    StereoPipeline seeded({});
    StereoPipeline voting(voting_params);
    ASSERT_TRUE(seeded.set_calibration(r.calib).ok());
    ASSERT_TRUE(voting.set_calibration(r.calib).ok());
    (void)seeded.step(r.frame.left, r.frame.right, false);
    (void)voting.step(r.frame.left, r.frame.right, false);
    const sb::ball_detector::PositionPrior near{truth + cv::Vec3d(0.004, -0.003, 0.01), 0.3};
    const auto a = seeded.step(r.frame.left, r.frame.right, false, near);
    const auto b = voting.step(r.frame.left, r.frame.right, false, near);
    ASSERT_EQ(a.status, DetectionStatus::kFound) << a.reason;
    ASSERT_EQ(b.status, DetectionStatus::kFound) << b.reason;
    EXPECT_EQ(a.search, sb::ball_detector::SearchPath::kExpectedOutlines);
    EXPECT_EQ(b.search, sb::ball_detector::SearchPath::kPriorWindow);
    EXPECT_NEAR(a.left.x_px, b.left.x_px, 0.3);
    EXPECT_NEAR(a.left.y_px, b.left.y_px, 0.3);
    EXPECT_NEAR(a.right.x_px, b.right.x_px, 0.3);
    EXPECT_LT(norm3(a.position_m - b.position_m), 0.003);
    EXPECT_LT(norm3(a.position_m - truth), 0.01 * truth[2]);

    const sb::ball_detector::PositionPrior aside{truth + cv::Vec3d(0.08, 0.0, 0.0), 0.3};
    const auto c = seeded.step(r.frame.left, r.frame.right, false, aside);
    ASSERT_EQ(c.status, DetectionStatus::kFound) << c.reason;
    EXPECT_EQ(c.search, sb::ball_detector::SearchPath::kPriorWindow);
    EXPECT_LT(norm3(c.position_m - a.position_m), 0.003);
  }
}

// Unsynchronised eyes: the row allowance follows from the skew between the exposures and the
// ball's speed, in radii of its outline (pairing_test: what the pairing does with it).
TEST(StereoPipelineSkew, GivenSpeedAndSkewThenTheMotionIsTheirProductInBallRadii) {
  sb::ball_detector::BallDetectorParams p;
  p.ball_diameter_m = 0.24;
  // Given the paper's rows (no speed), then no allowance whatever the stamps say
  p.epipolar_ball_speed_mps = 0.0;
  EXPECT_EQ(StereoPipeline(p).motion_radii(8'000'000, std::nullopt), 0.0);
  // Given 3 m/s and the skew from the frame's stamps (8 ms, either sign), then 0.2 radii; no
  // measured skew: none
  p.epipolar_ball_speed_mps = 3.0;
  p.epipolar_skew_ns = -1;
  const StereoPipeline measured(p);
  EXPECT_NEAR(measured.motion_radii(8'000'000, std::nullopt), 0.2, 1e-12);
  EXPECT_NEAR(measured.motion_radii(-8'000'000, std::nullopt), 0.2, 1e-12);
  EXPECT_EQ(measured.motion_radii(std::nullopt, std::nullopt), 0.0);
  // Given a configured skew (stills), then it replaces the stamps'
  p.epipolar_skew_ns = 16'000'000;
  const StereoPipeline stills(p);
  EXPECT_NEAR(stills.motion_radii(0, std::nullopt), 0.4, 1e-12);
  // Given a following track of a ball at rest, then its speed plus the slack bounds the motion
  sb::ball_detector::PositionPrior still{{0.0, 0.0, 2.0}, 0.3, {0.0, 0.0, 0.0}};
  EXPECT_NEAR(stills.motion_radii(0, still), sb::ball_detector::kTrackSpeedSlackMps * 0.016 / 0.12,
              1e-12);
  sb::ball_detector::PositionPrior fast{{0.0, 0.0, 2.0}, 0.3, {0.0, 9.0, 0.0}};
  EXPECT_NEAR(stills.motion_radii(0, fast), 0.4, 1e-12);
}

// A k chosen for 640 px sees a ball's arc at 2304 px as a straight segment: wider images get
// the detector's windows and lengths scaled, in steps of whole k.
TEST(DetectorScaling, GivenAWiderImageThenKAndLengthsScaleWithItsWidth) {
  sb::ball_detector::PixelToPixelParams p;
  p.k_values = {3, 5};
  p.min_radius_px = 4.0;
  p.max_radius_px = 250.0;
  p.min_separation_px = 10.0;
  p.refine_params.clutter_min_radius_px = 30.0;
  // Given 1152 px against a 640 px reference (1.8x), then k 5 and 9, lengths x1.8
  const auto wide = sb::ball_detector::scaled_to_width(p, 640, 1152);
  EXPECT_EQ(wide.k_values, (std::vector<int>{5, 9}));
  EXPECT_NEAR(wide.min_radius_px, 7.2, 1e-9);
  EXPECT_NEAR(wide.max_radius_px, 450.0, 1e-9);
  EXPECT_NEAR(wide.min_separation_px, 18.0, 1e-9);
  EXPECT_NEAR(wide.refine_params.clutter_min_radius_px, 54.0, 1e-9);
  // Given the reference width, a narrower one, one a pixel wider (no k changes) or 0 (off),
  // then the settings as configured
  for (const auto& [ref, width] : {std::pair{640, 640}, {640, 320}, {640, 641}, {0, 2304}}) {
    const auto same = sb::ball_detector::scaled_to_width(p, ref, width);
    EXPECT_EQ(same.k_values, p.k_values);
    EXPECT_EQ(same.min_radius_px, p.min_radius_px);
  }
  // k stays within the detector's range
  EXPECT_EQ(sb::ball_detector::scaled_to_width(p, 100, 4000).k_values.back(), 31);
}
