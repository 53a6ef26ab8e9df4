// Baselines and the factory: every method finds a plain ball through the common interface.

#include "ball_detector/core/baselines.hpp"
#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/synthetic.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <cmath>

namespace stereoball::ball_detector {
namespace {

TEST(Factory, GivenEachMethodNameThenADetectorOfThatNameFindsAPlainBall) {
  const auto scene = make_scene(SceneKind::kPlain, {320, 240}, 5);
  DetectorOptions o;
  o.min_radius_px = 8;
  o.max_radius_px = 60;
  o.min_score = 0.3;
  for (const auto& name : detector_names()) {
    std::string err;
    auto det = make_detector(name, o, &err);
    ASSERT_NE(det, nullptr) << name << ": " << err;
    EXPECT_EQ(det->name(), name);
    const auto found = det->detect(scene.image);
    ASSERT_FALSE(found.empty()) << name;
    EXPECT_LT(std::hypot(found[0].x_px - scene.truth[0].x_px, found[0].y_px - scene.truth[0].y_px),
              2.0)
        << name;
    EXPECT_NEAR(found[0].radius_px, scene.truth[0].radius_px, 3.0) << name;
    EXPECT_GE(found[0].score, 0.0);
    EXPECT_LE(found[0].score, 1.0);
  }
}

TEST(Factory, GivenAnUnknownMethodOrBadOptionThenAnErrorNamesIt) {
  std::string err;
  EXPECT_EQ(make_detector("sobel", DetectorOptions{}, &err), nullptr);
  EXPECT_NE(err.find("sobel"), std::string::npos);
  DetectorOptions o;
  o.max_radius_px = 1.0;
  EXPECT_EQ(make_detector("p2p", o, &err), nullptr);
  EXPECT_NE(err.find("max_radius_px"), std::string::npos);
}

TEST(GradientVoting, GivenTheSameBallThenItCastsMoreVotesThanPixelToPixel) {
  const auto scene = make_scene(SceneKind::kClutter, {352, 288}, 1);
  GradientVotingDetector grad(GradientVotingParams{});
  PixelToPixelDetector p2p(PixelToPixelParams{});
  grad.detect(scene.image);
  p2p.detect(scene.image);
  EXPECT_GT(grad.diagnostics()->increments, 2 * p2p.diagnostics()->increments);
  EXPECT_GT(grad.diagnostics()->voters, p2p.diagnostics()->voters);
}

TEST(CandidateOptionsOf, GivenEitherVotingDetectorsParamsThenTheSharedFieldsAreCopied) {
  // Given gradient-voting params and Pixel-to-Pixel params with the shared fields set alike
  GradientVotingParams g;
  g.box_size_px = 7;
  g.min_separation_px = 13.0;
  g.min_score = 0.61;
  g.max_circles = 9;
  g.refine = false;
  g.refine_params.band_px = 2.5;
  PixelToPixelParams p;
  p.box_size_px = 7;
  p.min_separation_px = 13.0;
  p.min_score = 0.61;
  p.max_circles = 9;
  p.refine = false;
  p.refine_params.band_px = 2.5;
  // When their candidate options are made for radii 6-40 px
  const CandidateOptions a = candidate_options_of(g, RadiusRange{6.0, 40.0});
  const CandidateOptions b = candidate_options_of(p, RadiusRange{6.0, 40.0});
  // Then both carry the radii, the box's line tolerance and the shared fields, and the options
  // only Pixel-to-Pixel sets keep their defaults
  for (const CandidateOptions& o : {a, b}) {
    EXPECT_EQ(o.min_radius_px, 6.0);
    EXPECT_EQ(o.max_radius_px, 40.0);
    EXPECT_EQ(o.line_tolerance_px, 4.5);
    EXPECT_EQ(o.min_separation_px, 13.0);
    EXPECT_EQ(o.min_score, 0.61);
    EXPECT_EQ(o.max_circles, 9);
    EXPECT_FALSE(o.refine);
    EXPECT_EQ(o.refine_params.band_px, 2.5);
    EXPECT_FALSE(o.polish);
    EXPECT_FALSE(o.nested_circles);
  }
}

TEST(Cht, GivenBadParamsThenValidateNamesThem) {
  ChtParams p;
  EXPECT_TRUE(p.validate().ok());
  p.radius_step_px = 0.0;
  EXPECT_NE(p.validate().error().find("radius_step_px"), std::string::npos);
  OpenCvHoughParams o;
  o.alt = true;
  o.param2 = 5.0;
  EXPECT_NE(o.validate().error().find("param2"), std::string::npos);
}

TEST(EdCircles, GivenAFlatEllipseAndACircleThenOnlyTheCircleIsReported) {
  cv::Mat img(240, 320, CV_8UC3, cv::Scalar(40, 40, 40));
  cv::circle(img, {90, 120}, 40, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
  cv::ellipse(img, {{230.f, 120.f}, {120.f, 50.f}, 0.f}, cv::Scalar(200, 200, 200), cv::FILLED,
              cv::LINE_AA);
  EdCirclesParams p;
  p.max_radius_px = 100;
  const auto found = EdCirclesDetector(p).detect(img);
  ASSERT_EQ(found.size(), 1u);
  EXPECT_NEAR(found[0].x_px, 90.0, 1.5);
  EXPECT_NEAR(found[0].radius_px, 40.0, 2.0);
}

TEST(EdCircles, GivenBadParamsThenValidateNamesThem) {
  EdCirclesParams p;
  EXPECT_TRUE(p.validate().ok());
  p.min_axis_ratio = 1.5;
  EXPECT_NE(p.validate().error().find("min_axis_ratio"), std::string::npos);
  p = EdCirclesParams{};
  p.gradient_threshold = 0;
  EXPECT_NE(p.validate().error().find("gradient_threshold"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::ball_detector
