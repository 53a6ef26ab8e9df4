// Pairing of left/right candidates: row check, triangulation, size check, best pair.

#include "ball_detector/pipeline/pairing.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "ball_detector/pipeline/synthetic_pairing_fixture.hpp"

namespace sb = stereoball;
using sb::ball_detector::Circle;
using sb::ball_detector::PairingStatus;

namespace {

class Pairing : public sb::ball_detector::testing::SyntheticPairingTest {
 protected:
  Pairing() : SyntheticPairingTest(0.25) {}

  // Rectified circles of the 0.22 m ball centred at (x, y, z) metres, left/right.
  std::pair<Circle, Circle> ball_at(double x0, double y0, double z0, double score = 0.9,
                                    double radius_scale = 1.0) const {
    return {outline_in_eye({x0, y0, z0}, false, score, radius_scale),
            outline_in_eye({x0, y0, z0}, true, score, radius_scale)};
  }
};

}  // namespace

TEST_F(Pairing, GivenEmptyEye_ThenNoCandidateNamingTheEye) {
  const auto [l, r] = ball_at(0.1, 0.0, 1.5);
  auto res = pair_candidates(ctx_, {l}, {});
  EXPECT_EQ(res.status, PairingStatus::kNoCandidate);
  EXPECT_NE(res.reason.find("right"), std::string::npos);
  res = pair_candidates(ctx_, {}, {});
  EXPECT_EQ(res.status, PairingStatus::kNoCandidate);
  EXPECT_NE(res.reason.find("either"), std::string::npos);
}

TEST_F(Pairing, GivenTrueBall_ThenFoundAtItsPosition) {
  const auto [l, r] = ball_at(0.2, -0.1, 1.5);
  const auto res = pair_candidates(ctx_, {l}, {r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->position_m[0], 0.2, 1e-6);
  EXPECT_NEAR(res.best->position_m[1], -0.1, 1e-6);
  EXPECT_NEAR(res.best->position_m[2], 1.5, 1e-6);
  EXPECT_NEAR(res.best->depth_from_size_m, 1.5, 1e-6);
  EXPECT_NEAR(res.best->row_residual_px, 0.0, 0.05);
}

// Given circles 2.5 px apart in rows (paper tolerance 2 px), then mismatch; at 1.9 px, found.
TEST_F(Pairing, GivenRowDifferenceAroundTolerance_ThenOnlyWithinAccepted) {
  auto [l, r] = ball_at(0.0, 0.0, 1.5);
  r.y_px += 2.5;
  auto res = pair_candidates(ctx_, {l}, {r});
  EXPECT_EQ(res.status, PairingStatus::kEpipolarMismatch) << res.reason;
  r.y_px -= 0.6;
  res = pair_candidates(ctx_, {l}, {r});
  EXPECT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->row_residual_px, 1.9, 1e-9);
}

TEST_F(Pairing, GivenNegativeDisparity_ThenMismatch) {
  auto [l, r] = ball_at(0.0, 0.0, 1.5);
  std::swap(l.x_px, r.x_px);
  EXPECT_EQ(pair_candidates(ctx_, {l}, {r}).status, PairingStatus::kEpipolarMismatch);
}

// Given a circle three times too small for a ball at its triangulated depth (a far-away
// round object at the wrong disparity), then size inconsistent with the numbers in the reason.
TEST_F(Pairing, GivenWrongSize_ThenSizeInconsistent) {
  const auto [l, r] = ball_at(0.0, 0.0, 1.5, 0.9, 1.0 / 3.0);
  const auto res = pair_candidates(ctx_, {l}, {r});
  EXPECT_EQ(res.status, PairingStatus::kSizeInconsistent);
  EXPECT_NE(res.reason.find("should be"), std::string::npos) << res.reason;
  EXPECT_EQ(res.row_matches, 1);
  EXPECT_EQ(res.size_matches, 0);
}

// Given a decoy on the same row with a higher score but the wrong size, and the true ball,
// then the true ball is chosen; between two consistent pairs the higher score wins.
TEST_F(Pairing, GivenSeveralCandidates_ThenBestConsistentPairByScore) {
  const auto [bl, br] = ball_at(-0.3, 0.0, 1.5, 0.7);
  const auto [dl, dr] = ball_at(0.3, 0.0, 1.5, 0.95, 0.4);
  auto res = pair_candidates(ctx_, {dl, bl}, {dr, br});
  ASSERT_EQ(res.status, PairingStatus::kFound);
  EXPECT_EQ(res.best->left_index, 1u);
  EXPECT_EQ(res.best->right_index, 1u);

  const auto [gl, gr] = ball_at(0.3, 0.05, 2.0, 0.9);
  res = pair_candidates(ctx_, {bl, gl}, {br, gr});
  ASSERT_EQ(res.status, PairingStatus::kFound);
  EXPECT_EQ(res.best->left_index, 1u);
  EXPECT_NEAR(res.best->position_m[2], 2.0, 1e-6);
}

TEST(BetterPair, GivenEqualScores_ThenSmallerRowResidualWins) {
  sb::ball_detector::StereoPair a, b;
  a.score = b.score = 0.8;
  a.row_residual_px = 0.3;
  b.row_residual_px = 1.2;
  EXPECT_TRUE(better_pair(a, b));
  EXPECT_FALSE(better_pair(b, a));
  b.score = 0.9;
  EXPECT_TRUE(better_pair(b, a));
}

// Given a ball at several depths and sides, the box searched in the right eye holds its right
// circle with room for the whole disc, and is a small part of the image.
TEST_F(Pairing, GivenLeftCircleThenPartnerBoxHoldsTheTruePartnerOnly) {
  const cv::Size image(640, 480);
  for (const cv::Vec3d& c :
       {cv::Vec3d(0.0, 0.0, 1.0), cv::Vec3d(0.3, 0.1, 1.5), cv::Vec3d(-0.4, -0.05, 2.5)}) {
    const auto [l, r] = ball_at(c[0], c[1], c[2]);
    const cv::Rect box = sb::ball_detector::partner_search_box(ctx_, l, image, 8);
    ASSERT_FALSE(box.empty()) << c;
    EXPECT_TRUE(box.contains(
        cv::Point(static_cast<int>(r.x_px - r.radius_px), static_cast<int>(r.y_px - r.radius_px))))
        << c << " box " << box;
    EXPECT_TRUE(box.contains(
        cv::Point(static_cast<int>(r.x_px + r.radius_px), static_cast<int>(r.y_px + r.radius_px))))
        << c << " box " << box;
    // The disc, plus the size tolerance's disparity spread: a small part of the image.
    EXPECT_LT(box.area(), image.area() / 4) << c << " box " << box;
  }
  // A left circle whose partner would lie left of the image gives an empty box.
  Circle edge{5.0, 240.0, 60.0, 0.9};
  EXPECT_TRUE(sb::ball_detector::partner_search_box(ctx_, edge, image, 8).width < 2 * 60);
}

// Given a better-scoring look-alike pair and the ball's pair, when the tracker expects the
// ball near its true place, then the ball's pair is chosen; without the prior, the look-alike;
// with a prior far from both, the best score again.
TEST_F(Pairing, GivenTrackPrior_ThenPairNearItWinsOverBetterScore) {
  const auto [bl, br] = ball_at(0.3, 0.0, 1.5, 0.7);
  const auto [dl, dr] = ball_at(-0.4, -0.1, 2.0, 0.95);
  const sb::ball_detector::PositionPrior near_ball{cv::Vec3d(0.32, 0.0, 1.45), 0.3};
  auto res = pair_candidates(ctx_, {dl, bl}, {dr, br}, near_ball);
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->position_m[0], 0.3, 0.01);
  res = pair_candidates(ctx_, {dl, bl}, {dr, br});
  ASSERT_EQ(res.status, PairingStatus::kFound);
  EXPECT_NEAR(res.best->position_m[0], -0.4, 0.01);
  const sb::ball_detector::PositionPrior elsewhere{cv::Vec3d(1.5, 0.0, 3.0), 0.3};
  res = pair_candidates(ctx_, {dl, bl}, {dr, br}, elsewhere);
  EXPECT_NEAR(res.best->position_m[0], -0.4, 0.01);
}

// Given tracks in various states and ages, then a prior exists only for a following track
// with a valid position no older than the limit, moved on by its velocity.
TEST(TrackPrior, GivenTrackStateAndAge_ThenPriorOnlyWhenFollowingAndFresh) {
  sb::ball_detector::TrackedBall t;
  t.following = true;
  t.position_valid = true;
  t.position_m = {0.1, 0.0, 2.0};
  t.velocity_mps = {0.0, 0.0, -1.0};
  t.capture_stamp_ns = 1'000'000'000;
  const auto p = sb::ball_detector::prior_from_track(t, 1'100'000'000, 0.3, 500'000'000);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->position_m[2], 1.9, 1e-9);  // 0.1 s at -1 m/s
  EXPECT_DOUBLE_EQ(p->gate_m, 0.3);
  EXPECT_FALSE(sb::ball_detector::prior_from_track(t, 1'600'000'001, 0.3, 500'000'000));
  EXPECT_FALSE(sb::ball_detector::prior_from_track(t, 1'100'000'000, 0.0, 500'000'000));
  auto searching = t;
  searching.following = false;
  EXPECT_FALSE(sb::ball_detector::prior_from_track(searching, 1'100'000'000, 0.3, 500'000'000));
  auto invalid = t;
  invalid.position_valid = false;
  EXPECT_FALSE(sb::ball_detector::prior_from_track(invalid, 1'100'000'000, 0.3, 500'000'000));
}

// Given a prior at the ball, the left search box holds the ball's whole left circle; a prior
// behind the camera gives no box.
TEST_F(Pairing, GivenPriorThenLeftSearchBoxHoldsTheBallsDisc) {
  const cv::Size image(640, 480);
  for (const cv::Vec3d& c : {cv::Vec3d(0.0, 0.0, 1.0), cv::Vec3d(0.3, 0.1, 1.5)}) {
    const auto [l, r] = ball_at(c[0], c[1], c[2]);
    const sb::ball_detector::PositionPrior prior{c + cv::Vec3d(0.06, 0.0, -0.06), 0.3};
    const cv::Rect box = sb::ball_detector::prior_search_box(ctx_, prior, image, 9);
    ASSERT_FALSE(box.empty());
    EXPECT_TRUE(box.contains(
        cv::Point(static_cast<int>(l.x_px - l.radius_px), static_cast<int>(l.y_px - l.radius_px))))
        << box;
    EXPECT_TRUE(box.contains(
        cv::Point(static_cast<int>(l.x_px + l.radius_px), static_cast<int>(l.y_px + l.radius_px))))
        << box;
    if (c[2] >= 1.5) {
      EXPECT_LT(box.area(), image.area() / 2) << box;
    }
  }
  const sb::ball_detector::PositionPrior behind{cv::Vec3d(0.0, 0.0, -1.0), 0.3};
  EXPECT_TRUE(sb::ball_detector::prior_search_box(ctx_, behind, image, 9).empty());
}

// Given balls far off the axis (where the outline is an ellipse larger than the on-axis
// radius) and near, then each is found at its position, size consistent within 1 %.
TEST_F(Pairing, GivenBallsOffTheAxisAndNearThenSizeIsJudgedOnTheirEllipse) {
  for (const cv::Vec3d& c :
       {cv::Vec3d(-0.55, 0.3, 0.9), cv::Vec3d(0.6, -0.25, 1.0), cv::Vec3d(0.1, 0.15, 0.45)}) {
    const auto [l, r] = ball_at(c[0], c[1], c[2]);
    const auto res = pair_candidates(ctx_, {l}, {r});
    ASSERT_EQ(res.status, PairingStatus::kFound) << c << ": " << res.reason;
    EXPECT_LT(std::abs(res.best->size_error), 0.01) << c;
    EXPECT_NEAR(res.best->depth_from_size_m, c[2], 1e-6) << c;
    EXPECT_LT(cv::norm(res.best->position_m - c), 1e-4) << c;
    // Off the axis the on-axis radius would misjudge the size by more than 8 %.
    const double on_axis = sb::stereo::expected_radius_px(tri_.focal_px(), 0.22, c[2]);
    if (std::hypot(c[0], c[1]) / c[2] > 0.6) {
      EXPECT_GT(0.5 * (l.radius_px + r.radius_px) / on_axis - 1.0, 0.08) << c;
    }
  }
}

// Given a floor 0.3 m below a level camera, a ball resting on it is found; the same ball-sized
// pair 0.4 m higher (a plate on a box) is rejected as off the floor, naming the height, and
// without a floor model it would be found.
TEST_F(Pairing, GivenAFloorThenOnlyABallRestingOnItIsFound) {
  sb::ball_detector::PairingContext on_floor{epi_, tri_, size_,
                                             sb::ball_detector::FloorModel{{0, -1, 0}, 0.3, 0.1}};
  const double resting_y = 0.3 - 0.11;  // y is down: the centre one radius above the floor
  const auto [bl, br] = ball_at(0.2, resting_y, 1.6);
  auto res = pair_candidates(on_floor, {bl}, {br});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->height_error_m, 0.0, 1e-6);

  const auto [pl, pr] = ball_at(-0.3, resting_y - 0.4, 1.8);
  res = pair_candidates(on_floor, {pl}, {pr});
  EXPECT_EQ(res.status, PairingStatus::kOffFloor);
  EXPECT_NEAR(res.best->height_error_m, 0.4, 1e-6);
  EXPECT_NE(res.reason.find("0.40 m above"), std::string::npos) << res.reason;
  EXPECT_EQ(pair_candidates(ctx_, {pl}, {pr}).status, PairingStatus::kFound);

  // Both: the ball on the floor wins even when the plate scores higher.
  const auto [hl, hr] = ball_at(-0.3, resting_y - 0.4, 1.8, 0.99);
  res = pair_candidates(on_floor, {hl, bl}, {hr, br});
  ASSERT_EQ(res.status, PairingStatus::kFound);
  EXPECT_EQ(res.best->left_index, 1u);
}

// Given a prior, the radius range it allows holds the ball's radius there and excludes a
// ball twice as near or twice as far; a partner range holds the right circle of each left one.
TEST_F(Pairing, GivenAPriorOrLeftCirclesThenTheRadiusRangesHoldTheBallOnly) {
  const cv::Vec3d c(0.3, 0.1, 1.5);
  const auto [l, r] = ball_at(c[0], c[1], c[2]);
  const auto range =
      sb::ball_detector::prior_radius_range(ctx_, sb::ball_detector::PositionPrior{c, 0.3});
  EXPECT_LT(range.min_px, l.radius_px);
  EXPECT_GT(range.max_px, l.radius_px);
  EXPECT_GT(range.min_px, ball_at(c[0], c[1], 2.0 * c[2]).first.radius_px);
  EXPECT_LT(range.max_px, ball_at(c[0], c[1], 0.5 * c[2]).first.radius_px);
  const auto [l2, r2] = ball_at(-0.2, 0.0, 0.8);
  const auto partners = sb::ball_detector::partner_radius_range(ctx_, {l, l2});
  for (const Circle& right : {r, r2}) {
    EXPECT_LT(partners.min_px, right.radius_px);
    EXPECT_GT(partners.max_px, right.radius_px);
  }
}

// Given a ball's left outline, then every right outline along its line of sight lies on the
// left circle's rows (both eyes' outlines touch the same epipolar planes), they run from the
// nearest ball (leftmost) outwards, and one of them is the ball's own right outline.
TEST_F(Pairing, GivenALeftCircleThenPartnerOutlinesLieOnItsRowsAndHoldTheTruePartner) {
  const auto [l, r] = ball_at(0.25, 0.12, 0.6);
  const auto outlines = partner_outlines(ctx_, l, 0.25);
  ASSERT_GT(outlines.size(), 10u);
  double closest = 1e9;
  for (size_t i = 0; i < outlines.size(); ++i) {
    EXPECT_NEAR(outlines[i].y_px, l.y_px, 0.05) << i;
    if (i > 0) {
      EXPECT_GT(outlines[i].x_px, outlines[i - 1].x_px) << i;
    }
    closest = std::min(closest, std::hypot(outlines[i].x_px - r.x_px, outlines[i].y_px - r.y_px));
  }
  EXPECT_LT(closest, 0.3);
  EXPECT_TRUE(partner_outlines(ctx_, Circle{100, 100, -5, 0.9}, 0.25).empty());
  // A size tolerance of 10 (the most validation allows) spans 0 .. 11 times the disparity: the
  // step coarsens so that no more than 257 outlines are scored.
  sb::stereo::SizeCheckParams loose{0.22, 10.0};
  const sb::ball_detector::PairingContext wide{epi_, tri_, loose, std::nullopt};
  const auto many = partner_outlines(wide, l, 0.25);
  EXPECT_GT(many.size(), 100u);
  EXPECT_LE(many.size(), 257u);
}

// Given a scorer that peaks on the ball's right outline, then the predicted partner is that
// outline (to the fine step) and pairs with the left circle at the ball's position; a scorer
// that never reaches min_score gives none.
TEST_F(Pairing, GivenAScorerPeakingOnTheTruePartnerThenPredictedPartnerFindsIt) {
  const auto [l, r] = ball_at(0.25, 0.12, 0.6);
  const auto peaked = [&, r = r](const Circle& c) {
    return std::max(0.0, 1.0 - 0.1 * std::abs(c.x_px - r.x_px));
  };
  const auto p = predicted_partner(ctx_, l, peaked, 0.55);
  ASSERT_TRUE(p.has_value());
  EXPECT_NEAR(p->x_px, r.x_px, 0.3);
  EXPECT_NEAR(p->y_px, r.y_px, 0.05);
  EXPECT_GT(p->score, 0.97);
  const auto res = pair_candidates(ctx_, {l}, {*p});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->position_m[2], 0.6, 0.003);
  EXPECT_FALSE(predicted_partner(
                   ctx_, l, [](const Circle&) { return 0.5; }, 0.55)
                   .has_value());
}

// Given priors inside the image, at its bottom border and far below it, then the centre margin
// is 0, about the distance outside plus the slack, and capped at the ball's largest radius.
TEST_F(Pairing, GivenPriorsInsideAndBelowTheImageThenTheCentreMarginCoversWhereTheCentreCanBe) {
  const cv::Size image = calib_.image_size;
  EXPECT_EQ(prior_centre_margin_px(ctx_, {cv::Vec3d(0.0, 0.0, 1.5), 0.3}, image), 0);
  const sb::ball_detector::PositionPrior at_border{cv::Vec3d(0.0, 0.25, 0.5), 0.3};
  const int m = prior_centre_margin_px(ctx_, at_border, image);
  const auto radii = prior_radius_range(ctx_, at_border);
  EXPECT_GT(m, 0);
  EXPECT_LE(m, radii.max_px);
  const sb::ball_detector::PositionPrior below{cv::Vec3d(0.0, 2.0, 0.5), 0.3};
  EXPECT_LE(prior_centre_margin_px(ctx_, below, image),
            static_cast<int>(std::ceil(prior_radius_range(ctx_, below).max_px)));
  // The right eye's partners of a circle at the left border lie beyond it.
  const auto [l, r] = ball_at(-0.2, 0.0, 0.5);
  (void)r;
  EXPECT_GT(partner_centre_margin_px(ctx_, {l}, image), 0);
  const auto [lc, rc] = ball_at(0.05, 0.0, 1.5);
  (void)rc;
  EXPECT_EQ(partner_centre_margin_px(ctx_, {lc}, image), 0);
}

// Given a floor, then a partner is sought (the scorer called) for a ball resting on it and not
// for a ball-sized circle 0.4 m above it, whose pair would fail the floor check anyway.
TEST_F(Pairing, GivenAFloorThenPredictedPartnerIsSoughtOnlyForBallsThatCanRestOnIt) {
  const sb::ball_detector::PairingContext on_floor{
      epi_, tri_, size_, sb::ball_detector::FloorModel{{0, -1, 0}, 0.3, 0.1}};
  const double resting_y = 0.3 - 0.11;
  int calls = 0;
  const auto counting = [&calls](const Circle&) {
    ++calls;
    return 0.9;
  };
  const auto [bl, br] = ball_at(0.2, resting_y, 1.6);
  (void)br;
  EXPECT_TRUE(predicted_partner(on_floor, bl, counting, 0.55).has_value());
  EXPECT_GT(calls, 0);
  calls = 0;
  const auto [pl, pr] = ball_at(-0.3, resting_y - 0.4, 1.8);
  (void)pr;
  EXPECT_FALSE(predicted_partner(on_floor, pl, counting, 0.55).has_value());
  EXPECT_EQ(calls, 0);
  EXPECT_TRUE(predicted_partner(ctx_, pl, counting, 0.55).has_value());  // no floor model
}

TEST_F(Pairing, GivenOutlineRadiiThatDisagreeThenTheSmallerEyeIsRefittedAtTheOthersRadius) {
  using sb::ball_detector::radius_balance;
  // A ball off the axis: the eyes' outlines differ a little, as their views do
  const cv::Vec3d at(0.4, 0.1, 2.5);
  auto [l, r] = ball_at(at[0], at[1], at[2]);
  EXPECT_FALSE(radius_balance(tri_, l, r, at, 0.11, 0.3, 0.02).has_value());
  // The right fit pulled 0.8 px inwards: the right eye, at the radius its outline has
  Circle pulled = r;
  pulled.radius_px -= 0.8;
  auto b = radius_balance(tri_, l, pulled, at, 0.11, 0.3, 0.02);
  ASSERT_TRUE(b.has_value());
  EXPECT_TRUE(b->right_eye);
  EXPECT_NEAR(b->radius_px, r.radius_px, 0.01);
  // The left one pulled: the left eye
  pulled = l;
  pulled.radius_px -= 0.8;
  b = radius_balance(tri_, pulled, r, at, 0.11, 0.3, 0.02);
  ASSERT_TRUE(b.has_value());
  EXPECT_FALSE(b->right_eye);
  EXPECT_NEAR(b->radius_px, l.radius_px, 0.01);
  // A difference within the fit's noise: nothing to refit
  pulled.radius_px = l.radius_px - 0.2;
  EXPECT_FALSE(radius_balance(tri_, pulled, r, at, 0.11, 0.3, 0.02).has_value());
}

// Unsynchronised eyes (motion_radii): the ball moved between the two exposures.
class UnsynchronisedPairing : public Pairing {
 protected:
  UnsynchronisedPairing() {
    // 3 m/s for 8 ms: 0.024 m, 0.22 of the ball's radius.
    moving_ctx_.motion_radii = 3.0 * 0.008 / 0.11;
  }
  sb::ball_detector::PairingContext moving_ctx_{epi_, tri_, size_, std::nullopt};
};

// Given a ball 1.5 m away that rose 0.02 m between the left and the right exposure (its right
// outline 6 rows above the left: three times the paper's tolerance), when paired with the
// allowance for its motion, then it is found at its depth; with the paper's rows it is not.
TEST_F(UnsynchronisedPairing, GivenBallMovingVerticallyBetweenShots_ThenPaired) {
  const auto [l, r0] = ball_at(0.1, 0.0, 1.5);
  const auto [l1, r] = ball_at(0.1, -0.02, 1.5);
  ASSERT_GT(std::abs(l.y_px - r.y_px), 5.0);
  EXPECT_EQ(pair_candidates(ctx_, {l}, {r}).status, PairingStatus::kEpipolarMismatch);
  const auto res = pair_candidates(moving_ctx_, {l}, {r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_NEAR(res.best->position_m[2], 1.5, 0.02);
  EXPECT_NEAR(res.best->position_m[1], -0.01, 0.005);  // between the two exposures
}

// Given the ball moving sideways as well (0.02 m: its disparity then says 1.29 m, too near for
// its radii within a 10 % size tolerance), when paired with the allowance, then it is found,
// marked moved, at the triangulated position; with the paper's rows it is not.
TEST_F(UnsynchronisedPairing, GivenBallMovingAcrossBetweenShots_ThenPairedAsMoved) {
  const sb::stereo::SizeCheckParams tight{0.22, 0.10};
  sb::ball_detector::PairingContext ctx{epi_, tri_, tight, std::nullopt};
  const auto [l, r0] = ball_at(0.1, 0.0, 1.5);
  const auto [l1, r] = ball_at(0.08, -0.01, 1.5);
  EXPECT_NE(pair_candidates(ctx, {l}, {r}).status, PairingStatus::kFound);
  ctx.motion_radii = moving_ctx_.motion_radii;
  const auto res = pair_candidates(ctx, {l}, {r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_TRUE(res.best->moved);
  EXPECT_NEAR(res.best->position_m[2], tri_.depth_from_disparity_m(l.x_px - r.x_px).value(), 0.02);
  // A partner that far off in disparity beyond the motion is not the ball.
  Circle farther = r;
  farther.x_px -= 25.0;
  EXPECT_NE(pair_candidates(ctx, {l}, {farther}).status, PairingStatus::kFound);
}

// Given a static clutter pair at the same row offset: two small round things 5 m away whose
// circles lie as many rows apart as the moving ball's did, when paired with the same
// allowance, then they are not paired (a small outline moves few rows in the skew).
TEST_F(UnsynchronisedPairing, GivenStaticClutterPairAtTheSameOffset_ThenNotPaired) {
  const auto [bl, br0] = ball_at(0.1, 0.0, 1.5);
  const auto [bl1, br] = ball_at(0.1, -0.02, 1.5);
  const double offset_px = bl.y_px - br.y_px;
  auto [cl, cr] = ball_at(-0.4, 0.1, 5.0);
  cr.y_px = cl.y_px - offset_px;
  const auto res = pair_candidates(moving_ctx_, {cl}, {cr});
  EXPECT_EQ(res.status, PairingStatus::kEpipolarMismatch) << res.reason;
  EXPECT_NE(res.reason.find("radius"), std::string::npos) << res.reason;
  // Nor a partner of another size at that offset next to the ball.
  Circle other = br;
  other.radius_px *= 0.6;
  EXPECT_NE(pair_candidates(moving_ctx_, {bl}, {other}).status, PairingStatus::kFound);
}

// Given the track's prior says the ball stands still, when the pipeline's allowance is worked
// out, then the track's speed bounds it (see stereo_pipeline_test for the pipeline's side).
TEST_F(UnsynchronisedPairing, GivenPriorFromTrack_ThenItCarriesTheTrackVelocity) {
  sb::ball_detector::TrackedBall track;
  track.following = true;
  track.position_valid = true;
  track.position_m = {0.0, 0.0, 2.0};
  track.velocity_mps = {0.0, -1.0, 0.0};
  track.capture_stamp_ns = 1'000'000'000;
  const auto prior = sb::ball_detector::prior_from_track(track, 1'100'000'000, 0.3, 500'000'000);
  ASSERT_TRUE(prior.has_value());
  EXPECT_NEAR(prior->velocity_mps[1], -1.0, 1e-12);
  EXPECT_NEAR(prior->position_m[1], -0.1, 1e-9);
}

// Given unsynchronised eyes, a small circle in clutter whose disparity misses its size (it
// pairs only thanks to the motion allowance) scoring above the ball, and the larger ball whose
// disparity fits its size, when paired with a dominance margin, then the ball is reported;
// with the margin 0 (the paper's ranking by score) the small circle wins.
TEST_F(UnsynchronisedPairing, GivenSmallMovedCircleAndLargerConsistentBall_ThenTheBallWins) {
  const sb::stereo::SizeCheckParams tight{0.22, 0.10};
  sb::ball_detector::PairingContext ctx{epi_, tri_, tight, std::nullopt};
  ctx.motion_radii = moving_ctx_.motion_radii;
  const auto [ball_l, ball_r] = ball_at(0.1, 0.0, 1.5, 0.75);
  auto [small_l, small_r] = ball_at(-0.4, -0.3, 4.0, 0.9);
  small_r.x_px -= 2.0;  // its disparity says nearer than its size: paired only as moved
  auto res = pair_candidates(ctx, {small_l, ball_l}, {small_r, ball_r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  ASSERT_TRUE(res.best->moved) << "the fixture must make the small pair a moved one";
  EXPECT_EQ(res.best->left_index, 0u);
  ctx.dominance_margin = 0.2;
  res = pair_candidates(ctx, {small_l, ball_l}, {small_r, ball_r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_EQ(res.best->left_index, 1u);
  EXPECT_NEAR(res.best->position_m[2], 1.5, 0.03);
}

// Given a weak small pair that fits its size and a much stronger, larger pair of equal radii on
// allowed rows whose disparity does not fit its size (the ball moved more than allowed), when
// paired with a dominance margin, then nothing is reported (size inconsistent, the strong pair
// named); without the margin the weak pair is reported.
TEST_F(UnsynchronisedPairing, GivenStrongerOutlinesFailingSize_ThenTheWeakPairIsNotReported) {
  sb::ball_detector::PairingContext ctx{epi_, tri_, size_, std::nullopt};
  ctx.motion_radii = moving_ctx_.motion_radii;
  const auto [weak_l, weak_r] = ball_at(-0.5, 0.3, 2.5, 0.6);
  auto [ball_l, ball_r] = ball_at(0.1, 0.0, 1.5, 0.95);
  ball_r.x_px += 40.0;  // disparity of a ball far beyond its size's depth
  auto res = pair_candidates(ctx, {ball_l, weak_l}, {ball_r, weak_r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_EQ(res.best->left_index, 1u);
  ctx.dominance_margin = 0.2;
  res = pair_candidates(ctx, {ball_l, weak_l}, {ball_r, weak_r});
  EXPECT_EQ(res.status, PairingStatus::kSizeInconsistent);
  EXPECT_NE(res.reason.find("stronger outlines"), std::string::npos) << res.reason;
}

// The dominance rule stands for what unsynchronised eyes do (the ball moved more than allowed
// between the exposures): with synchronised eyes (no motion allowance, the simulator's and the
// paper's rows) the same outlines leave the weak size-consistent pair reported.
TEST_F(UnsynchronisedPairing, GivenSynchronisedEyes_ThenDominanceDoesNotWithdrawThePair) {
  sb::ball_detector::PairingContext ctx{epi_, tri_, size_, std::nullopt};
  ctx.dominance_margin = 0.2;
  ctx.motion_radii = 0.0;
  const auto [weak_l, weak_r] = ball_at(-0.5, 0.3, 2.5, 0.6);
  auto [ball_l, ball_r] = ball_at(0.1, 0.0, 1.5, 0.95);
  ball_r.x_px += 40.0;
  const auto res = pair_candidates(ctx, {ball_l, weak_l}, {ball_r, weak_r});
  ASSERT_EQ(res.status, PairingStatus::kFound) << res.reason;
  EXPECT_EQ(res.best->left_index, 1u);
}
