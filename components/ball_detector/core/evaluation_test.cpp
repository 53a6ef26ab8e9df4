// Evaluation helpers and the synthetic suite used by the bench.

#include "ball_detector/core/evaluation.hpp"
#include "ball_detector/core/synthetic.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <string>
#include <vector>

namespace stereoball::ball_detector {
namespace {

TEST(CircleIou, GivenIdenticalDisjointAndNestedDiscsThenIouIsExact) {
  EXPECT_DOUBLE_EQ(circle_iou({0, 0, 5, 0}, {0, 0, 5, 0}), 1.0);
  EXPECT_DOUBLE_EQ(circle_iou({0, 0, 5, 0}, {20, 0, 5, 0}), 0.0);
  EXPECT_NEAR(circle_iou({0, 0, 10, 0}, {1, 0, 5, 0}), 0.25, 1e-12);
}

TEST(CircleIou, GivenHalfOverlapThenIouMatchesTheLensArea) {
  // Two unit circles one radius apart: lens area = 2*pi/3 - sqrt(3)/2.
  const double lens = 2.0 * std::numbers::pi / 3.0 - std::sqrt(3.0) / 2.0;
  EXPECT_NEAR(circle_iou({0, 0, 1, 0}, {1, 0, 1, 0}), lens / (2 * std::numbers::pi - lens), 1e-9);
}

TEST(MatchCircles, GivenDetectionsThenTruePositivesFalsePositivesAndMissesAreCounted) {
  const std::vector<Circle> truth{{10, 10, 5, 1}, {50, 50, 8, 1}};
  const std::vector<Circle> dets{{10.2, 10, 5, 0.9}, {10, 10, 5, 0.5}, {90, 90, 5, 0.8}};
  const auto m = match_circles(dets, truth, 0.8);
  EXPECT_EQ(m.true_positives, 1);
  EXPECT_EQ(m.false_positives, 2);  // duplicate and stray
  EXPECT_EQ(m.false_negatives, 1);
  ASSERT_EQ(m.centre_errors_px.size(), 1u);
  EXPECT_NEAR(m.centre_errors_px[0], 0.2, 1e-9);
  const auto s = detection_scores(m.true_positives, m.false_positives, m.false_negatives);
  EXPECT_NEAR(s.precision, 1.0 / 3.0, 1e-12);
  EXPECT_NEAR(s.recall, 0.5, 1e-12);
  EXPECT_NEAR(s.f1, 0.4, 1e-12);
}

TEST(Synthetic, GivenTheSameSeedThenScenesAreIdenticalAndDifferentSeedsDiffer) {
  const auto a = make_scene(SceneKind::kClutter, {160, 120}, 7);
  const auto b = make_scene(SceneKind::kClutter, {160, 120}, 7);
  const auto c = make_scene(SceneKind::kClutter, {160, 120}, 8);
  EXPECT_EQ(cv::norm(a.image, b.image, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a.image, c.image, cv::NORM_INF), 0.0);
}

TEST(Synthetic, GivenEveryKindThenItsNameIsTheBenchsKeyAndAnUnknownValueIsAQuestionMark) {
  // Given every scene kind, When named, Then each has its own name (bench-detect keys its
  // per-kind figures by them) and a value outside the enum gets "?".
  const std::vector<std::string> expected = {"plain",   "two-colour", "lighting", "noise",
                                             "blur",    "occlusion",  "clutter",  "multiple",
                                             "no-ball", "lines-only"};
  ASSERT_EQ(static_cast<std::size_t>(SceneKind::kLinesOnly) + 1, expected.size());
  for (std::size_t k = 0; k < expected.size(); ++k)
    EXPECT_EQ(scene_kind_name(static_cast<SceneKind>(k)), expected[k]) << k;
  EXPECT_EQ(scene_kind_name(static_cast<SceneKind>(expected.size())), "?");
}

TEST(Synthetic, GivenTheSuiteThenBallsLieInsideAndBallFreeKindsHaveNoTruth) {
  const auto suite = make_suite({352, 288}, 2, 1);
  EXPECT_EQ(suite.size(), 20u);
  for (const auto& s : suite) {
    const bool ball_free = s.kind == SceneKind::kNoBall || s.kind == SceneKind::kLinesOnly;
    EXPECT_EQ(s.truth.empty(), ball_free) << scene_kind_name(s.kind);
    for (const auto& t : s.truth) {
      EXPECT_GE(t.x_px - t.radius_px, 0.0);
      EXPECT_LE(t.x_px + t.radius_px, 351.0);
      EXPECT_GE(t.y_px - t.radius_px, 0.0);
      EXPECT_LE(t.y_px + t.radius_px, 287.0);
    }
  }
}

}  // namespace
}  // namespace stereoball::ball_detector
