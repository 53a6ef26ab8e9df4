#include "stereo/core/still_board.hpp"

#include <gtest/gtest.h>

namespace stereoball::stereo {
namespace {

constexpr int64_t kMs = 1'000'000;

std::vector<cv::Point2f> board_at(float dx, float dy = 0.0f) {
  std::vector<cv::Point2f> pts;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) pts.emplace_back(100.0f + 20.0f * c + dx, 80.0f + 20.0f * r + dy);
  return pts;
}

StillBoardParams params() {
  StillBoardParams p;
  p.max_motion_px = 0.5;
  p.still_ns = 200 * kMs;
  p.max_gap_ns = 100 * kMs;
  return p;
}

// Feeds both eyes at 30 Hz from t0 to t1 (right eye skew_ns later), the board at x(t) in the
// left eye and x(t) - 30 px in the right; returns the poses taken.
template <typename F>
std::vector<StillPose> feed(StillBoardSelector& s, int64_t t0, int64_t t1, int64_t skew_ns, F x) {
  std::vector<StillPose> taken;
  for (int64_t t = t0; t < t1; t += 33 * kMs) {
    if (auto p = s.add(Eye::kLeft, t, board_at(x(t)))) taken.push_back(*p);
    const int64_t tr = t + skew_ns;
    if (auto p = s.add(Eye::kRight, tr, board_at(x(tr) - 30.0f))) taken.push_back(*p);
  }
  return taken;
}

TEST(StillBoardSelector, TakesOnePoseWhenBothEyesHoldStill) {
  // Given a board standing still in both eyes for a second
  StillBoardSelector s(params());
  // When both eyes report it at 30 Hz
  const auto taken = feed(s, 0, 1000 * kMs, 0, [](int64_t) { return 0.0f; });
  // Then exactly one pose is taken, after the still time, with both eyes' corners
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_GE(taken[0].left_stamp_ns - taken[0].still_from_ns, 200 * kMs);
  EXPECT_FLOAT_EQ(taken[0].left_px[0].x, 100.0f);
  EXPECT_FLOAT_EQ(taken[0].right_px[0].x, 70.0f);
}

TEST(StillBoardSelector, MovingBoardIsNeverTaken) {
  // Given a board moving 1 px per frame (never still for 200 ms)
  StillBoardSelector s(params());
  // When both eyes report it
  const auto taken = feed(s, 0, 2000 * kMs, 0, [](int64_t t) { return t / (33.0f * kMs); });
  // Then no pose is taken
  EXPECT_TRUE(taken.empty());
  EXPECT_LT(s.stillness(Eye::kLeft).still_ns, 200 * kMs);
}

TEST(StillBoardSelector, HoldsMovesAndHoldsAgainGivesTwoPoses) {
  // Given a board held 0.5 s, moved 40 px over 0.3 s, held again 0.5 s
  StillBoardSelector s(params());
  const auto x = [](int64_t t) {
    if (t < 500 * kMs) return 0.0f;
    if (t < 800 * kMs) return 40.0f * static_cast<float>(t - 500 * kMs) / (300.0f * kMs);
    return 40.0f;
  };
  // When the eyes run free, the right one 15 ms behind the left
  const auto taken = feed(s, 0, 1300 * kMs, 15 * kMs, x);
  // Then one pose per hold, each eye's corners from the hold (not from the move)
  ASSERT_EQ(taken.size(), 2u);
  EXPECT_FLOAT_EQ(taken[0].left_px[0].x, 100.0f);
  EXPECT_FLOAT_EQ(taken[1].left_px[0].x, 140.0f);
  EXPECT_FLOAT_EQ(taken[1].right_px[0].x, 110.0f);
  EXPECT_GE(taken[1].still_from_ns, 800 * kMs);
}

TEST(StillBoardSelector, StillInOneEyeOnlyIsNotTaken) {
  // Given the left eye sees a still board and the right eye never finds it
  StillBoardSelector s(params());
  std::optional<StillPose> any;
  for (int64_t t = 0; t < 1000 * kMs; t += 33 * kMs) {
    if (auto p = s.add(Eye::kLeft, t, board_at(0))) any = p;
    if (auto p = s.add(Eye::kRight, t, {})) any = p;
  }
  // Then nothing is taken, and the eyes' states say why
  EXPECT_FALSE(any.has_value());
  EXPECT_TRUE(s.stillness(Eye::kLeft).board_seen);
  EXPECT_FALSE(s.stillness(Eye::kRight).board_seen);
}

TEST(StillBoardSelector, EyesStillAtDifferentTimesDoNotOverlap) {
  // Given the left eye saw the board still from 0 to 300 ms and the right from 300 to 600 ms
  StillBoardSelector s(params());
  std::optional<StillPose> any;
  for (int64_t t = 0; t <= 300 * kMs; t += 33 * kMs)
    any = any ? any : s.add(Eye::kLeft, t, board_at(0));
  for (int64_t t = 300 * kMs; t <= 600 * kMs; t += 33 * kMs)
    any = any ? any : s.add(Eye::kRight, t, board_at(0));
  // Then no pose: the two still intervals share less than the still time
  EXPECT_FALSE(any.has_value());
}

TEST(StillBoardSelector, GapRestartsTheRun) {
  // Given a still board whose left camera stalls for 300 ms (longer than max_gap)
  StillBoardSelector s(params());
  int taken = 0;
  for (int64_t t = 0; t < 1000 * kMs; t += 33 * kMs) {
    if (t < 150 * kMs || t > 450 * kMs) taken += s.add(Eye::kLeft, t, board_at(0)) ? 1 : 0;
    taken += s.add(Eye::kRight, t, board_at(-30)) ? 1 : 0;
    // Then the left run restarted after the gap: no pose before 200 ms of new left frames
    if (t > 450 * kMs && t < 650 * kMs) {
      EXPECT_EQ(taken, 0) << "at " << t / kMs << " ms";
    }
  }
  EXPECT_EQ(taken, 1);
}

TEST(StillBoardSelector, ParamsValidateNamesTheField) {
  StillBoardParams p = params();
  p.max_motion_px = 0.0;
  const auto st = p.validate();
  ASSERT_FALSE(st);
  EXPECT_NE(st.error().find("max_motion_px"), std::string::npos);
  EXPECT_TRUE(params().validate());
}

TEST(MaxCornerMotion, DifferentCountsAreInfinitelyFar) {
  EXPECT_FALSE(std::isfinite(max_corner_motion_px(board_at(0), {})));
  EXPECT_NEAR(max_corner_motion_px(board_at(0), board_at(3, 4)), 5.0, 1e-6);
}

}  // namespace
}  // namespace stereoball::stereo
