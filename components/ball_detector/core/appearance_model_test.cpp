#include "ball_detector/core/appearance_model.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>

namespace stereoball::ball_detector {
namespace {

constexpr std::int64_t kFrameNs = 33'000'000;

// Pixels of a one-colour ball (BGR at full light) under shading from 30 % to 100 % of the light,
// with sensor noise.
std::vector<cv::Vec3b> shaded_ball(cv::Vec3d bgr, std::uint32_t seed, double min_light = 0.3) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> light(min_light, 1.0);
  std::normal_distribution<double> noise(0.0, 2.0);
  std::vector<cv::Vec3b> px;
  for (int i = 0; i < 200; ++i) {
    const double l = light(rng);
    px.push_back(cv::Vec3b(cv::saturate_cast<uchar>(bgr[0] * l + noise(rng)),
                           cv::saturate_cast<uchar>(bgr[1] * l + noise(rng)),
                           cv::saturate_cast<uchar>(bgr[2] * l + noise(rng))));
  }
  return px;
}

ColourHistogram hist(const std::vector<cv::Vec3b>& px) {
  auto h = ColourHistogram::of(px, 12);
  EXPECT_TRUE(h.has_value());
  return h.value_or(ColourHistogram{});
}

const cv::Vec3d kOrangeBgr{20, 110, 230}, kYellowOrange{20, 170, 230}, kBlue{200, 90, 30};

TEST(AppearanceModel, LearnsTheFollowedBallAndMatchesItInShade) {
  // Given a model that has seen the lit orange ball for frames_to_learn frames
  AppearanceModel m{AppearanceParams{}};
  EXPECT_FALSE(m.ready());
  for (int i = 0; i < 3; ++i) m.learn(hist(shaded_ball(kOrangeBgr, i, 0.7)), i * kFrameNs);
  // Then it is ready, and the same ball mostly in shadow still matches it closely
  ASSERT_TRUE(m.ready());
  const auto dark = m.similarity(hist(shaded_ball(kOrangeBgr, 99, 0.25)));
  ASSERT_TRUE(dark.has_value());
  EXPECT_GT(*dark, 0.85);
  EXPECT_FALSE(m.rejects(hist(shaded_ball(kOrangeBgr, 98, 0.25))));
}

TEST(AppearanceModel, RanksTheCloserColourFirst) {
  AppearanceModel m{AppearanceParams{}};
  for (int i = 0; i < 3; ++i) m.learn(hist(shaded_ball(kOrangeBgr, i)), i * kFrameNs);
  const double same = *m.similarity(hist(shaded_ball(kOrangeBgr, 50)));
  const double near = *m.similarity(hist(shaded_ball(kYellowOrange, 51)));
  const double far = *m.similarity(hist(shaded_ball(kBlue, 52)));
  EXPECT_GT(same, near);
  EXPECT_GT(near, far);
}

TEST(AppearanceModel, RejectsABallOfAnotherColour) {
  // Given the model of an orange ball
  AppearanceModel m{AppearanceParams{}};
  for (int i = 0; i < 3; ++i) m.learn(hist(shaded_ball(kOrangeBgr, i)), i * kFrameNs);
  // Then a blue ball (same pixels count, same shading) is rejected, an orange one is not
  EXPECT_TRUE(m.rejects(hist(shaded_ball(kBlue, 7))));
  EXPECT_FALSE(m.rejects(hist(shaded_ball(kOrangeBgr, 7))));
  // And a candidate too small to sample is never rejected for its colour
  EXPECT_FALSE(m.rejects(ColourHistogram::of({cv::Vec3b(200, 90, 30)}, 12)));
}

// Pixels of a two-colour ball (panels or stripes) showing fraction_first of its first colour.
std::vector<cv::Vec3b> two_colour_ball(cv::Vec3d first, cv::Vec3d second, double fraction_first,
                                       std::uint32_t seed) {
  auto a = shaded_ball(first, seed), b = shaded_ball(second, seed + 1000);
  const auto n_first = static_cast<std::size_t>(fraction_first * 200.0);
  std::vector<cv::Vec3b> px(a.begin(), a.begin() + static_cast<std::ptrdiff_t>(n_first));
  px.insert(px.end(), b.begin(), b.begin() + static_cast<std::ptrdiff_t>(200 - n_first));
  return px;
}

TEST(AppearanceModel, KeepsATwoColourBallWhateverPartOfItFacesTheCamera) {
  // Given the model of a pink ball with pale green panels, learnt while mostly pink showed
  const cv::Vec3d pink{180, 90, 230}, pale_green{170, 240, 180};
  AppearanceModel m{AppearanceParams{}};
  for (int i = 0; i < 3; ++i)
    m.learn(hist(two_colour_ball(pink, pale_green, 0.8, i)), i * kFrameNs);
  // When it has rolled to show mostly its panels, the proportions are reversed
  const auto rolled = hist(two_colour_ball(pink, pale_green, 0.15, 40));
  // Then it is still the followed ball (the proportions moved the Bhattacharyya coefficient,
  // not the colours), while a blue ball of the same shading is rejected
  EXPECT_LT(*m.similarity(rolled), *m.similarity(hist(two_colour_ball(pink, pale_green, 0.8, 41))));
  EXPECT_FALSE(m.rejects(rolled));
  EXPECT_GT(*m.containment(rolled), 0.9);
  EXPECT_TRUE(m.rejects(hist(shaded_ball(kBlue, 42))));
}

TEST(AppearanceModel, NothingIsRankedOrRejectedBeforeLearning) {
  AppearanceModel m{AppearanceParams{}};
  m.learn(hist(shaded_ball(kOrangeBgr, 1)), 0);
  m.learn(hist(shaded_ball(kOrangeBgr, 2)), kFrameNs);
  EXPECT_FALSE(m.ready());
  EXPECT_FALSE(m.similarity(hist(shaded_ball(kBlue, 3))).has_value());
  EXPECT_FALSE(m.rejects(hist(shaded_ball(kBlue, 3))));
}

TEST(AppearanceModel, ForgetsAfterALossLongerThanTheTimeout) {
  // Given a ready model with a 1 s timeout, last sample at t = 0.1 s
  AppearanceParams p;
  p.forget_after_ns = 1'000'000'000;
  AppearanceModel m{p};
  for (int i = 0; i < 3; ++i) m.learn(hist(shaded_ball(kOrangeBgr, i)), 50'000'000 * i);
  // When the ball is lost for just under the timeout, Then the model is kept
  m.tick(100'000'000 + 999'000'000);
  EXPECT_TRUE(m.ready());
  EXPECT_TRUE(m.rejects(hist(shaded_ball(kBlue, 5))));
  // When the loss goes past it, Then everything is forgotten: a blue ball is no longer rejected
  m.tick(100'000'000 + 1'001'000'000);
  EXPECT_FALSE(m.ready());
  EXPECT_EQ(m.samples(), 0);
  EXPECT_FALSE(m.rejects(hist(shaded_ball(kBlue, 5))));
  // And a new ball is learnt from scratch
  for (int i = 0; i < 3; ++i)
    m.learn(hist(shaded_ball(kBlue, 10 + i)), 2'000'000'000 + i * kFrameNs);
  EXPECT_TRUE(m.rejects(hist(shaded_ball(kOrangeBgr, 6))));
}

TEST(AppearanceModel, HistogramIsNormalisedAndGreyGoesToOneBin) {
  const auto h = hist(std::vector<cv::Vec3b>(20, cv::Vec3b(128, 128, 128)));
  EXPECT_DOUBLE_EQ(h.bin(ColourHistogram::kBins - 1), 1.0);
  const auto o = hist(shaded_ball(kOrangeBgr, 3));
  double sum = 0.0;
  for (int i = 0; i < ColourHistogram::kBins; ++i) sum += o.bin(i);
  EXPECT_NEAR(sum, 1.0, 1e-9);
  EXPECT_NEAR(o.similarity(o), 1.0, 1e-9);
  EXPECT_FALSE(ColourHistogram::of({}, 1).has_value());
}

TEST(AppearanceModel, ValidateNamesTheField) {
  AppearanceParams p;
  p.min_similarity = 1.5;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("appearance.min_similarity"), std::string::npos);
  p = {};
  p.forget_after_ns = -1;
  EXPECT_NE(p.validate().error().find("appearance.forget_after_ns"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::ball_detector
