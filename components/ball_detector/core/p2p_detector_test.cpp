// Pixel-to-Pixel end to end on synthetic images with known circles.

#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/synthetic.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <string>

#include "stereo/core/sphere_outline.hpp"

namespace stereoball::ball_detector {
namespace {

double centre_error(const Circle& a, const Circle& b) {
  return std::hypot(a.x_px - b.x_px, a.y_px - b.y_px);
}

PixelToPixelParams multi_k() {
  PixelToPixelParams p;
  p.k_values = {3, 5, 8};
  return p;
}

TEST(PixelToPixel, GivenPlainBallScenesThenTheBestCircleIsWithinOnePixel) {
  PixelToPixelDetector det(multi_k());
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const auto scene = make_scene(SceneKind::kPlain, {352, 288}, seed);
    const auto found = det.detect(scene.image);
    ASSERT_FALSE(found.empty()) << "seed " << seed;
    EXPECT_LT(centre_error(found[0], scene.truth[0]), 1.0) << "seed " << seed;
    EXPECT_NEAR(found[0].radius_px, scene.truth[0].radius_px, 1.5) << "seed " << seed;
    EXPECT_GE(found[0].score, 0.5);
    EXPECT_LE(found[0].score, 1.0);
  }
}

TEST(PixelToPixel, GivenTwoColourBallsThenTheCentreIsStillFound) {
  PixelToPixelDetector det(multi_k());
  int hits = 0;
  for (std::uint32_t seed = 1; seed <= 6; ++seed) {
    const auto scene = make_scene(SceneKind::kTwoColour, {352, 288}, seed);
    const auto found = det.detect(scene.image);
    hits += !found.empty() && centre_error(found[0], scene.truth[0]) < 1.0;
  }
  EXPECT_GE(hits, 5);
}

TEST(PixelToPixel, GivenCoarseToFineThenBallsAreFoundAtFullResolutionAccuracy) {
  // Given plain, two-colour and several-ball scenes at 640x480, and the detector searching the
  // halved image first (coarse_to_fine) beside the full-resolution one
  PixelToPixelParams p = multi_k();
  p.max_circles = 8;
  PixelToPixelDetector full(p);
  p.coarse_to_fine = true;
  PixelToPixelDetector coarse_to_fine(p);
  int balls = 0, found_by_both = 0;
  for (const SceneKind kind : {SceneKind::kPlain, SceneKind::kTwoColour, SceneKind::kMultiple})
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      const auto scene = make_scene(kind, {640, 480}, seed);
      // When both detect
      const auto a = full.detect(scene.image);
      const auto b = coarse_to_fine.detect(scene.image);
      for (const Circle& truth : scene.truth) {
        ++balls;
        auto nearest = [&](const std::vector<Circle>& found) -> const Circle* {
          const Circle* best = nullptr;
          for (const Circle& c : found)
            if (centre_error(c, truth) < 2.0 &&
                (!best || centre_error(c, truth) < centre_error(*best, truth)))
              best = &c;
          return best;
        };
        const Circle* fa = nearest(a);
        const Circle* fb = nearest(b);
        if (!fa) continue;
        // Then every ball the full search finds is found, with full-resolution accuracy: the
        // centre within 0.5 px of the full search's (not the 2 px of the halved image's grid)
        ASSERT_NE(fb, nullptr) << scene_kind_name(kind) << " seed " << seed;
        EXPECT_LT(centre_error(*fa, *fb), 0.5) << scene_kind_name(kind) << " seed " << seed;
        EXPECT_NEAR(fa->radius_px, fb->radius_px, 0.5) << scene_kind_name(kind) << " seed " << seed;
        EXPECT_GE(fb->score, p.min_score);
        ++found_by_both;
      }
    }
  EXPECT_GE(found_by_both, balls * 3 / 4);
}

TEST(PixelToPixel, GivenCoarseToFineAndSmallDiscsAmongLargeOnesThenTheSmallOnesAreFound) {
  // Given 640x480, radii searched from 12 px, and discs of 13-14 px (6.5-7 px in the halved
  // image) packed between large discs whose edge lines pass near the small ones' centres
  cv::Mat image(480, 640, CV_8UC3, cv::Scalar(40, 40, 40));
  std::vector<Circle> small;
  for (int i = 0; i < 6; ++i) {
    const Circle c{80.0 + 95.0 * i, 240.0, 13.0 + 0.2 * i, 0.0};
    cv::circle(image, {80 + 95 * i, 120}, 60, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
    cv::circle(image, {80 + 95 * i, 360}, 60, cv::Scalar(200, 200, 200), cv::FILLED, cv::LINE_AA);
    cv::circle(image, {static_cast<int>(c.x_px * 16), static_cast<int>(c.y_px * 16)},
               static_cast<int>(c.radius_px * 16), cv::Scalar(180, 180, 180), cv::FILLED,
               cv::LINE_AA, 4);
    small.push_back(c);
  }
  PixelToPixelParams p;
  p.k_values = {3};
  p.min_radius_px = 12.0;
  p.max_radius_px = 96.0;
  p.max_circles = 20;
  p.coarse_to_fine = true;
  PixelToPixelDetector det(p);
  // When it detects
  const auto found = det.detect(image);
  // Then every small disc is found within a pixel
  for (const Circle& c : small) {
    const bool hit = std::any_of(found.begin(), found.end(), [&](const Circle& f) {
      return centre_error(f, c) < 1.0 && std::abs(f.radius_px - c.radius_px) < 1.0;
    });
    EXPECT_TRUE(hit) << c.x_px;
  }
}

TEST(PixelToPixel, GivenCoarseToFineOnImagesWithoutCirclesThenFalseCirclesAreAsRareAsAtFullSize) {
  // Given lines and corners only, at both suite sizes (corners of thin lines can make a small
  // round-looking outline: the full-resolution search reports one on 2 of these 16 images)
  PixelToPixelParams p = multi_k();
  PixelToPixelDetector full(p);
  p.coarse_to_fine = true;
  PixelToPixelDetector coarse_to_fine(p);
  std::size_t false_full = 0, false_coarse = 0;
  for (const cv::Size size : {cv::Size(352, 288), cv::Size(640, 480)})
    for (std::uint32_t seed = 1; seed <= 8; ++seed) {
      const auto scene = make_scene(SceneKind::kLinesOnly, size, seed);
      // When both detect
      false_full += full.detect(scene.image).size();
      false_coarse += coarse_to_fine.detect(scene.image).size();
    }
  // Then the search from the halved image reports at most one more false circle in all
  EXPECT_LE(false_coarse, false_full + 1);
  EXPECT_LE(false_coarse, 3u);
}

TEST(PixelToPixel, GivenCoarseToFineAndAnInvalidCoarseScoreThenValidationNamesIt) {
  PixelToPixelParams p;
  p.coarse_min_score = 1.5;
  const auto status = p.validate();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.error().find("coarse_min_score"), std::string::npos);
  p = PixelToPixelParams{};
  p.refine_params.give_up_below = -0.1;
  EXPECT_FALSE(p.validate().ok());
}

// A striped ball: a disc whose stripe boundaries (another colour) end on its outline, meeting
// it at right angles, every 12 px along it.
cv::Mat striped_ball(cv::Point centre, int radius) {
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(60, 60, 60));
  cv::circle(image, centre, radius, cv::Scalar(30, 90, 220), cv::FILLED, cv::LINE_AA);
  cv::Mat stripes(image.size(), CV_8UC1, cv::Scalar(0));
  for (int x = centre.x - radius; x < centre.x + radius; x += 12)
    cv::rectangle(stripes, cv::Rect(x, 0, 6, image.rows), cv::Scalar(255), cv::FILLED);
  cv::Mat disc(image.size(), CV_8UC1, cv::Scalar(0));
  cv::circle(disc, centre, radius, cv::Scalar(255), cv::FILLED);
  image.setTo(cv::Scalar(230, 230, 120), stripes & disc);
  return image;
}

TEST(PixelToPixel, GivenStripesEndingOnTheOutlineThenOrientationIsolationKeepsItsArcsVoting) {
  const cv::Mat image = striped_ball({160, 120}, 60);
  PixelToPixelParams with;
  with.k_values = {5};
  PixelToPixelParams without = with;
  without.isolate_by_orientation = false;
  PixelToPixelDetector on(with), off(without);
  const auto found_on = on.detect(image);
  off.detect(image);
  // The outline's windows where a stripe boundary joins it fail the count rule, also after
  // plain arc isolation (the boundary is connected to the arc); cut at the orientation change,
  // the arc votes: more voters, and the ball is the best circle.
  EXPECT_GT(on.voters().size(), off.voters().size() + 5);
  ASSERT_FALSE(found_on.empty());
  EXPECT_LT(std::hypot(found_on[0].x_px - 160.0, found_on[0].y_px - 120.0), 1.5);
  EXPECT_NEAR(found_on[0].radius_px, 60.0, 2.0);
}

TEST(PixelToPixel, GivenSeveralBallsThenEachIsReturnedSortedByScore) {
  PixelToPixelDetector det(multi_k());
  const auto scene = make_scene(SceneKind::kMultiple, {640, 480}, 3);
  const auto found = det.detect(scene.image);
  ASSERT_GE(found.size(), scene.truth.size());
  for (size_t i = 1; i < found.size(); ++i) EXPECT_GE(found[i - 1].score, found[i].score);
  for (const auto& t : scene.truth) {
    double best = 1e9;
    for (const auto& f : found) best = std::min(best, centre_error(f, t));
    EXPECT_LT(best, 1.0) << "ball at " << t.x_px << "," << t.y_px;
  }
}

TEST(PixelToPixel, GivenOnlyLinesAndCornersThenNothingScoresAboveThreshold) {
  PixelToPixelDetector det(multi_k());
  for (std::uint32_t seed = 1; seed <= 8; ++seed) {
    const auto scene = make_scene(SceneKind::kLinesOnly, {352, 288}, seed);
    EXPECT_TRUE(det.detect(scene.image).empty()) << "seed " << seed;
  }
}

TEST(PixelToPixel, GivenSeparatedSquaresAndTrianglesThenNoCircleIsReported) {
  cv::Mat img(288, 352, CV_8U, cv::Scalar(80));
  cv::rectangle(img, cv::Rect(40, 40, 60, 60), cv::Scalar(200), cv::FILLED);
  const std::vector<cv::Point> tri{{200, 200}, {300, 220}, {240, 120}};
  cv::fillConvexPoly(img, tri, cv::Scalar(20), cv::LINE_AA);
  PixelToPixelDetector det(multi_k());
  EXPECT_TRUE(det.detect(img).empty());
}

TEST(PixelToPixel, GivenMinSeparationThenNoTwoCentresAreCloser) {
  PixelToPixelParams p = multi_k();
  p.min_separation_px = 40.0;
  p.min_score = 0.0;
  p.max_circles = 10;
  PixelToPixelDetector det(p);
  const auto found = det.detect(make_scene(SceneKind::kClutter, {352, 288}, 2).image);
  for (size_t i = 0; i < found.size(); ++i)
    for (size_t j = i + 1; j < found.size(); ++j) {
      const double larger = std::max(found[i].radius_px, found[j].radius_px);
      if (std::abs(found[i].radius_px - found[j].radius_px) <
          PixelToPixelParams::kSameCircleRadiusRatio * larger) {
        EXPECT_GE(centre_error(found[i], found[j]), 40.0);
      }
    }
}

// A ball with one stripe round its cap, seen from the side: the cap (pink on green) is a full
// circle a few pixels off the outline's centre, better contrasted than the outline (green on
// grey).
cv::Mat ball_with_striped_cap(cv::Point centre, int radius_px, cv::Point cap_centre,
                              int cap_radius_px) {
  cv::Mat img(240, 320, CV_8UC3, cv::Scalar(120, 120, 120));
  cv::circle(img, centre, radius_px, cv::Scalar(60, 200, 70), cv::FILLED, cv::LINE_AA);
  cv::circle(img, cap_centre, cap_radius_px, cv::Scalar(230, 200, 240), cv::FILLED, cv::LINE_AA);
  return with_sensor_noise(img, 11);
}

TEST(PixelToPixel, GivenAStripedBallsCapNearItsCentreThenBothTheCapAndTheOutlineAreReturned) {
  // Given caps of 65-75 % of the outline's radius, 3.6-5.4 px off its centre (closer than
  // min_separation_px: their accumulator peaks merge)
  for (const int cap_radius_px : {29, 32, 34})
    for (const cv::Point offset : {cv::Point(-2, -5), cv::Point(3, -3), cv::Point(-4, -3)}) {
      const cv::Point centre(160, 120);
      const cv::Mat img = ball_with_striped_cap(centre, 45, centre + offset, cap_radius_px);
      // When P2P runs with its defaults
      const auto found = PixelToPixelDetector(PixelToPixelParams{}).detect(img);
      // Then the outline is among the circles (cv::circle's anti-aliased disc of radius r has
      // its outline about 1 px outside r), and so is the cap
      auto has = [&](cv::Point c, double r) {
        return std::any_of(found.begin(), found.end(), [&](const Circle& f) {
          return std::hypot(f.x_px - c.x, f.y_px - c.y) < 1.0 && std::abs(f.radius_px - r) < 1.0;
        });
      };
      const std::string what = "cap r " + std::to_string(cap_radius_px) + " off " +
                               std::to_string(offset.x) + "," + std::to_string(offset.y);
      for (const auto& f : found)
        printf("%s: %.1f %.1f %.1f %.2f\n", what.c_str(), f.x_px, f.y_px, f.radius_px, f.score);
      EXPECT_TRUE(has(centre, 46.0)) << what;
      EXPECT_TRUE(has(centre + offset, cap_radius_px + 1.0)) << what;
    }
}

TEST(PixelToPixel, GivenKThenItSelectsCircleSize) {
  // Paper fig. 10/11: small k favours small circles, large k large ones.
  cv::Mat img(288, 352, CV_8U, cv::Scalar(40));
  cv::circle(img, {60, 140}, 8, cv::Scalar(220), cv::FILLED, cv::LINE_AA);
  cv::circle(img, {230, 140}, 70, cv::Scalar(220), cv::FILLED, cv::LINE_AA);
  auto votes_near = [](const cv::Mat& acc, cv::Point c) {
    double m = 0;
    cv::minMaxLoc(acc(cv::Rect(c.x - 3, c.y - 3, 7, 7)), nullptr, &m);
    return m;
  };
  double ratio_small_k = 0, ratio_large_k = 0;
  for (int k : {3, 15}) {
    PixelToPixelParams p;
    p.k_values = {k};
    PixelToPixelDetector det(p);
    det.detect(img);
    const cv::Mat& acc = det.diagnostics()->accumulator;
    const double r = votes_near(acc, {60, 140}) / std::max(1e-9, votes_near(acc, {230, 140}));
    (k == 3 ? ratio_small_k : ratio_large_k) = r;
  }
  EXPECT_GT(ratio_small_k, 1.0);
  EXPECT_LT(ratio_large_k, 1.0);
}

TEST(PixelToPixel, GivenAnEmptyOrBadImageThenNoCirclesAndValidateExplains) {
  PixelToPixelDetector det(PixelToPixelParams{});
  EXPECT_TRUE(det.detect(cv::Mat()).empty());
  EXPECT_TRUE(det.detect(cv::Mat(10, 10, CV_32F, cv::Scalar(0))).empty());
  EXPECT_NE(validate_image(cv::Mat()).error().find("empty"), std::string::npos);
  EXPECT_NE(validate_image(cv::Mat(10, 10, CV_32F)).error().find("8-bit"), std::string::npos);
  EXPECT_TRUE(validate_image(cv::Mat(10, 10, CV_8UC3)).ok());
}

TEST(PixelToPixel, GivenGreyAndBgrVersionsOfOneImageThenResultsAgree) {
  const auto scene = make_scene(SceneKind::kPlain, {352, 288}, 9);
  cv::Mat grey;
  cv::cvtColor(scene.image, grey, cv::COLOR_BGR2GRAY);
  auto params = multi_k();
  params.edge.colour = false;  // the grey gradient of a BGR image is the grey image's
  PixelToPixelDetector det(params);
  const auto a = det.detect(scene.image);
  const auto b = det.detect(grey);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_NEAR(a[0].x_px, b[0].x_px, 1e-9);
  EXPECT_NEAR(a[0].y_px, b[0].y_px, 1e-9);
  PixelToPixelDetector colour(multi_k());  // default: colour gradient, same ball
  const auto c = colour.detect(scene.image);
  ASSERT_FALSE(c.empty());
  EXPECT_NEAR(c[0].x_px, b[0].x_px, 0.5);
  EXPECT_NEAR(c[0].y_px, b[0].y_px, 0.5);
}

// A ball on a floor that differ in the given BGR colours, with mild sensor noise.
cv::Mat ball_on_floor(cv::Scalar floor, cv::Scalar ball) {
  cv::Mat img(240, 320, CV_8UC3, floor);
  cv::circle(img, {150, 110}, 40, ball, cv::FILLED, cv::LINE_AA);
  return with_sensor_noise(img, 7);
}

void expect_ball_found(const cv::Mat& img, const std::string& what) {
  PixelToPixelParams p;
  p.k_values = {5, 8};
  PixelToPixelDetector det(p);
  const auto found = det.detect(img);
  ASSERT_FALSE(found.empty()) << what;
  EXPECT_NEAR(found[0].x_px, 150.0, 1.0) << what;
  EXPECT_NEAR(found[0].y_px, 110.0, 1.0) << what;
  EXPECT_NEAR(found[0].radius_px, 40.0, 1.0) << what;
}

TEST(ColourEdges, GivenABallDifferingFromTheFloorInOneChannelOnlyThenItIsFound) {
  const cv::Scalar floor(90, 110, 100);
  for (int c = 0; c < 3; ++c) {
    cv::Scalar ball = floor;
    ball[c] += 50.0;
    expect_ball_found(ball_on_floor(floor, ball), std::string("channel ") + "BGR"[c]);
  }
}

TEST(ColourEdges, GivenABallOfAnotherHueAtEqualBrightnessThenColourFindsItAndGreyCannot) {
  // Grey = 0.299 R + 0.587 G + 0.114 B: red ball 100.55, green floor 100.5.
  const cv::Mat img = ball_on_floor(cv::Scalar(82, 130, 50), cv::Scalar(100, 50, 200));
  cv::Mat grey;
  cv::cvtColor(img, grey, cv::COLOR_BGR2GRAY);
  ASSERT_NEAR(cv::mean(grey(cv::Rect(0, 0, 60, 60)))[0],
              cv::mean(grey(cv::Rect(135, 95, 30, 30)))[0], 1.5);
  expect_ball_found(img, "hue");
  PixelToPixelParams grey_params;
  grey_params.k_values = {5, 8};
  grey_params.edge.colour = false;
  EXPECT_TRUE(PixelToPixelDetector(grey_params).detect(img).empty());
}

// A small two-panel ball on a planked floor, as the simulator's randomised scenes show it: one
// panel contrasts well, the other is close to the floor's colour, and the boundary between
// them curves a few pixels inside the rim. Two plank joints pass behind it.
cv::Mat two_panel_ball_on_planks(cv::Point centre, int radius_px, int pale_step, int shift_px,
                                 int joint_width_px) {
  const cv::Scalar floor(90, 105, 95);
  cv::Mat img(120, 160, CV_8UC3, floor);
  const cv::Scalar joint(40, 50, 42);
  cv::line(img, {0, 30}, {160, 90}, joint, joint_width_px, cv::LINE_AA);
  cv::line(img, {0, 75}, {160, 45}, joint, joint_width_px, cv::LINE_AA);
  cv::Mat ball(img.size(), CV_8UC3, cv::Scalar(110, 30, 150));
  cv::Mat pale(img.size(), CV_8U, cv::Scalar(0));
  cv::circle(pale, {centre.x + shift_px, centre.y - 2}, radius_px, 255, cv::FILLED, cv::LINE_AA);
  ball.setTo(floor + cv::Scalar::all(pale_step), pale);
  cv::Mat disc(img.size(), CV_8U, cv::Scalar(0));
  cv::circle(disc, centre, radius_px, 255, cv::FILLED, cv::LINE_AA);
  ball.copyTo(img, disc);
  return with_sensor_noise(img, 3);
}

TEST(PixelToPixel, GivenSmallTwoPanelBallsOnPlanksThenTheRobustRescueFindsMoreAndLosesNone) {
  // Given 96 such balls (radius, pale panel's step above the floor, boundary, joint width)
  const cv::Point centre(80, 60);
  auto found_with = [&](double rescue_weak_from, const cv::Mat& img, int radius_px) {
    PixelToPixelParams p;
    p.rescue_weak_from = rescue_weak_from;
    for (const Circle& c : PixelToPixelDetector(p).detect(img))
      // cv::circle's anti-aliased disc of radius r has its outline about 1 px outside r.
      if (std::hypot(c.x_px - centre.x, c.y_px - centre.y) < 1.0 &&
          std::abs(c.radius_px - (radius_px + 1.0)) < 1.0)
        return true;
    return false;
  };
  int with_rescue = 0, without = 0;
  for (const int radius_px : {8, 10, 12, 14})
    for (const int pale_step : {8, 14, 20, 30})
      for (const int shift_px : {3, 5, 8})
        for (const int joint_px : {1, 2}) {
          const cv::Mat img =
              two_panel_ball_on_planks(centre, radius_px, pale_step, shift_px, joint_px);
          // When the detector runs with the rescue (the default) and without it (1.0 = off)
          const bool rescued = found_with(PixelToPixelParams{}.rescue_weak_from, img, radius_px);
          const bool plain = found_with(1.0, img, radius_px);
          with_rescue += rescued;
          without += plain;
          // Then a ball found without the rescue is still found with it
          EXPECT_TRUE(rescued || !plain) << "r " << radius_px << " step " << pale_step << " shift "
                                         << shift_px << " joint " << joint_px;
        }
  // And the rescue finds clearly more (a fit pulled off a weak outline is its case)
  EXPECT_GE(with_rescue, without + 5) << "with " << with_rescue << ", without " << without;
}

TEST(PixelToPixel, GivenImagesWithoutBallsThenTheRobustRescueAddsNoCircle) {
  // Given lines and corners, clutter and ball-free scenes at both suite sizes
  PixelToPixelParams p = multi_k();
  PixelToPixelDetector rescue(p);
  p.rescue_weak_from = 1.0;
  PixelToPixelDetector no_rescue(p);
  std::size_t with = 0, without = 0;
  for (const SceneKind kind : {SceneKind::kLinesOnly, SceneKind::kNoBall})
    for (const cv::Size size : {cv::Size(352, 288), cv::Size(640, 480)})
      for (std::uint32_t seed = 1; seed <= 8; ++seed) {
        const auto scene = make_scene(kind, size, seed);
        // When both detect
        with += rescue.detect(scene.image).size();
        without += no_rescue.detect(scene.image).size();
      }
  // Then the rescue reports no circle that the plain refinement does not
  EXPECT_EQ(with, without);
}

TEST(PixelToPixel, GivenSpotsJustInsideTheRimThenTheBestCircleStaysOnTheRimWithOrWithoutPolishing) {
  // An orange ball with white spots reaching to a pixel or two of its rim on grey: colour
  // edges see each spot's boundary beside the outline.
  const cv::Mat img = spotted_disc_image({240, 240}, {120, 120}, 45, 21, 22);
  auto best_with = [&](bool polish) {
    PixelToPixelParams p = multi_k();
    p.polish = polish;
    PixelToPixelDetector det(p);
    const auto circles = det.detect(img);
    return circles.empty() ? Circle{} : circles.front();
  };
  // Here the vote peak is good enough for least squares too (refine_circle's test shows a seed
  // it is not); polishing must not make it worse.
  const Circle truth{120, 120, 45, 0};
  for (const bool polish : {true, false}) {
    const Circle best = best_with(polish);
    EXPECT_LT(centre_error(best, truth), 0.15) << "polish " << polish;
    EXPECT_NEAR(best.radius_px, 45.0, 1.0) << "polish " << polish;
  }
}

TEST(PixelToPixel, GivenDiagnosticsThenVotesAreCountedAndThePeakIsSharp) {
  PixelToPixelDetector det(multi_k());
  const auto scene = make_scene(SceneKind::kPlain, {352, 288}, 4);
  det.detect(scene.image);
  const auto* d = det.diagnostics();
  ASSERT_NE(d, nullptr);
  EXPECT_GT(d->voters, 0);
  EXPECT_EQ(d->voters, static_cast<std::int64_t>(det.voters().size()));
  EXPECT_GT(d->increments, d->voters);
  EXPECT_GT(d->peak_to_mean, 5.0);
  EXPECT_EQ(d->edges.size(), scene.image.size());
}

// An image of a ball (filled, anti-aliased) with the outline a sphere at centre_m has in
// camera, or a true circle of the outline's mean radius at the same place.
cv::Mat sphere_image(const stereo::PinholeCamera& camera, const cv::Vec3d& centre_m, bool as_circle,
                     stereo::SphereOutline& outline) {
  outline = *stereo::sphere_outline(camera, centre_m, 0.11);
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar(60, 70, 80));
  const double angle_deg = std::atan2(outline.major_axis.y, outline.major_axis.x) * 180 / CV_PI;
  const cv::Point2f c(static_cast<float>(outline.centre_px.x),
                      static_cast<float>(outline.centre_px.y));
  if (as_circle) {
    const float r = static_cast<float>(outline.mean_radius_px());
    cv::ellipse(img, cv::RotatedRect(c, cv::Size2f(2 * r, 2 * r), 0.0f), cv::Scalar(30, 120, 240),
                cv::FILLED, cv::LINE_AA);
  } else {
    cv::ellipse(img,
                cv::RotatedRect(c,
                                cv::Size2f(static_cast<float>(2 * outline.semi_major_px),
                                           static_cast<float>(2 * outline.semi_minor_px)),
                                static_cast<float>(angle_deg)),
                cv::Scalar(30, 120, 240), cv::FILLED, cv::LINE_AA);
  }
  return img;
}

// Given spheres 25-40 degrees off the axis (outline ellipses with axes 10-25 % apart), when the
// detector knows the camera, then each scores near 1 with the ellipse's centre and mean radius;
// without the camera the same ball scores far lower, and a true circle there (a flat disc
// facing the camera) scores lower with the camera than a sphere does.
TEST(PixelToPixel, GivenTheCameraThenSpheresOffTheAxisAreMeasuredAsTheEllipsesTheyImageAs) {
  const stereo::PinholeCamera camera{400.0, {320.0, 240.0}};
  PixelToPixelParams p;
  p.max_radius_px = 150;
  p.min_score = 0.0;
  PixelToPixelDetector with_camera(p), without(p);
  with_camera.set_camera(camera);
  for (const cv::Vec3d& c :
       {cv::Vec3d(-0.5, 0.2, 1.0), cv::Vec3d(0.45, -0.3, 1.1), cv::Vec3d(-0.6, -0.35, 0.9)}) {
    stereo::SphereOutline o;
    const cv::Mat sphere = sphere_image(camera, c, false, o);
    const auto seen = with_camera.detect(sphere);
    ASSERT_FALSE(seen.empty()) << c;
    EXPECT_GT(seen[0].score, 0.95) << c;
    EXPECT_LT(std::hypot(seen[0].x_px - o.centre_px.x, seen[0].y_px - o.centre_px.y), 0.8) << c;
    EXPECT_NEAR(seen[0].radius_px, o.mean_radius_px(), 0.8) << c;
    const auto plain = without.detect(sphere);
    EXPECT_TRUE(plain.empty() || plain[0].score < seen[0].score - 0.2) << c;
    const auto disc = with_camera.detect(sphere_image(camera, c, true, o));
    EXPECT_TRUE(disc.empty() || disc[0].score < seen[0].score - 0.2) << c;
  }
  // On the axis a sphere is a circle: the camera changes nothing.
  stereo::SphereOutline o;
  const cv::Mat centred = sphere_image(camera, {0.0, 0.0, 1.0}, false, o);
  const auto a = with_camera.detect(centred), b = without.detect(centred);
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_NEAR(a[0].score, b[0].score, 1e-9);
  EXPECT_NEAR(a[0].radius_px, b[0].radius_px, 1e-6);
}

// A 400x300 image with one orange disc, and the thresholds of its own edge map (as the node
// passes a whole frame's to its crops).
struct DiscScene {
  cv::Mat image;
  EdgeThresholds thresholds;
};

DiscScene disc_scene(cv::Point centre, int radius_px) {
  DiscScene s{cv::Mat(300, 400, CV_8UC3, cv::Scalar(50, 60, 55)), {}};
  cv::circle(s.image, centre, radius_px, cv::Scalar(40, 170, 230), cv::FILLED, cv::LINE_AA);
  EdgeMap edges;
  compute_edge_map(s.image, PixelToPixelParams{}.edge, edges);
  s.thresholds = thresholds_of(edges);
  return s;
}

// Given a ball of radius 40 px, when the hints allow only other radii, then nothing is found;
// when they hold 40 px, it is; and a ball 60 % outside the image counts only when the hints'
// border rule lets a third of a circle do.
TEST(PixelToPixel, GivenSearchHintsThenOnlyTheirRadiiAndBorderRuleApply) {
  PixelToPixelDetector det(PixelToPixelParams{});
  const DiscScene whole = disc_scene({200, 150}, 40);
  EXPECT_TRUE(det.detect(whole.image, whole.thresholds, SearchHints{{60.0, 120.0}}).empty());
  EXPECT_TRUE(det.detect(whole.image, whole.thresholds, SearchHints{{4.0, 25.0}}).empty());
  const auto in_range = det.detect(whole.image, whole.thresholds, SearchHints{{30.0, 50.0}});
  ASSERT_FALSE(in_range.empty());
  EXPECT_NEAR(in_range[0].radius_px, 40.0, 1.0);

  const DiscScene cut = disc_scene({410, 150}, 40);
  EXPECT_TRUE(det.detect(cut.image, cut.thresholds).empty());
  const auto third = det.detect(cut.image, cut.thresholds, SearchHints{{4.0, 120.0}, 0.3});
  ASSERT_FALSE(third.empty());
  EXPECT_NEAR(third[0].x_px, 410.0, 1.5);
}

// Given a ball whose centre lies 40 px below the image (a third of its outline in view), then
// an image-sized accumulator has no cell for its centre and it is not found; with the hints'
// centre margin it is, at its true centre and size.
TEST(PixelToPixel, GivenACentreMarginThenACircleCentredOutsideTheImageIsFound) {
  PixelToPixelDetector det(PixelToPixelParams{});
  const DiscScene below = disc_scene({200, 340}, 80);
  const Circle truth{200, 340, 80, 0};
  SearchHints hints{{4.0, 120.0}, 0.3};
  const auto without = det.detect(below.image, below.thresholds, hints);
  EXPECT_TRUE(without.empty() || centre_error(without[0], truth) > 5.0);
  hints.centre_margin_px = 60;
  const auto with = det.detect(below.image, below.thresholds, hints);
  ASSERT_FALSE(with.empty());
  EXPECT_LT(centre_error(with[0], truth), 1.5);
  EXPECT_NEAR(with[0].radius_px, 80.0, 1.5);
  EXPECT_EQ(det.raw_accumulator().rows, 300 + 2 * 60);
  // No cell farther out than the largest radius searched.
  hints.centre_margin_px = 100'000;
  (void)det.detect(below.image, below.thresholds, hints);
  EXPECT_EQ(det.raw_accumulator().rows, 300 + 2 * 120);
}

// Given seeds a few pixels off balls in textured and two-colour scenes (as a tracker's
// prediction is), then detect_at_seeds refines each onto its ball as closely as the voting
// search does; a seed farther off than the first band, or a ball outside the hinted radii,
// gives nothing.
TEST(PixelToPixel, GivenSeedsNearTheBallThenDetectAtSeedsFindsWhatVotingFindsWithoutVoting) {
  PixelToPixelDetector det(PixelToPixelParams{});
  const SearchHints any{{4.0, 120.0}};
  for (const SceneKind kind : {SceneKind::kPlain, SceneKind::kTwoColour, SceneKind::kClutter}) {
    for (std::uint32_t seed = 1; seed <= 4; ++seed) {
      const auto scene = make_scene(kind, {352, 288}, seed);
      const std::string what =
          "kind " + std::to_string(static_cast<int>(kind)) + " seed " + std::to_string(seed);
      const Circle& truth = scene.truth[0];
      EdgeMap whole;
      compute_edge_map(scene.image, PixelToPixelParams{}.edge, whole);
      const EdgeThresholds thresholds = thresholds_of(whole);
      const auto voted = det.detect(scene.image, thresholds, any);
      ASSERT_FALSE(voted.empty()) << what;
      const Circle off{truth.x_px + 3.0, truth.y_px - 2.0, truth.radius_px + 1.5, 0.0};
      const auto seeded = det.detect_at_seeds(scene.image, thresholds, any, {&off, 1});
      ASSERT_EQ(seeded.size(), 1u) << what;
      EXPECT_LT(centre_error(seeded[0], truth), 1.0) << what;
      EXPECT_NEAR(seeded[0].radius_px, truth.radius_px, 1.5) << what;
      EXPECT_LT(centre_error(seeded[0], voted[0]), 0.5) << what;
      EXPECT_GE(seeded[0].score, PixelToPixelParams{}.min_score) << what;
      // Nothing votes: the accumulator is not touched.
      EXPECT_EQ(det.diagnostics()->voters, 0) << what;

      const Circle far{truth.x_px + 12.0, truth.y_px, truth.radius_px, 0.0};
      EXPECT_TRUE(det.detect_at_seeds(scene.image, thresholds, any, {&far, 1}).empty()) << what;
      const SearchHints other_radii{{truth.radius_px + 10.0, 200.0}};
      EXPECT_TRUE(det.detect_at_seeds(scene.image, thresholds, other_radii, {&off, 1}).empty())
          << what;
    }
  }
}

// Voters of a circle outline with isolated dots scattered around it, for one isolation setting.
std::int64_t voters_with_dots(bool isolate, double max_points_factor) {
  cv::Mat image = cv::Mat::zeros(200, 200, CV_8UC1);
  cv::circle(image, {100, 100}, 50, cv::Scalar(255), cv::FILLED);
  std::uint32_t state = 7;
  for (int i = 0; i < 500; ++i) {  // dots of one pixel, a different grey from both sides
    state = state * 1664525u + 1013904223u;
    const int x = 30 + static_cast<int>((state >> 8) % 140);
    const int y = 30 + static_cast<int>((state >> 20) % 140);
    image.at<std::uint8_t>(y, x) = 128;
  }
  PixelToPixelParams p;
  p.isolate_arc = isolate;
  p.isolate_max_points_factor = max_points_factor;
  PixelToPixelDetector det(p);
  (void)det.detect(image);
  return det.diagnostics()->voters;
}

TEST(PixelToPixel, GivenDotsAroundAnOutlineThenADenserIsolationLimitIsolatesMoreArcs) {
  // Given windows of the outline holding the arc plus a varying number of dot edges
  const std::int64_t paper = voters_with_dots(false, 3.0);
  // When the limit on the points a window may hold for isolation grows
  const std::int64_t none = voters_with_dots(true, 1.0);
  const std::int64_t twice = voters_with_dots(true, 2.0);
  const std::int64_t thrice = voters_with_dots(true, 3.0);
  // Then a limit of 2k+1 points isolates nothing (the paper's rule), and each larger limit
  // lets more of the crowded windows vote
  EXPECT_EQ(none, paper);
  EXPECT_GT(twice, none);
  EXPECT_GT(thrice, twice);
}

TEST(PixelToPixelParams, GivenBadFieldsThenValidateNamesThem) {
  PixelToPixelParams p;
  EXPECT_TRUE(p.validate().ok());
  p.k_values = {0};
  EXPECT_NE(p.validate().error().find("k_values"), std::string::npos);
  p = PixelToPixelParams{};
  p.box_size_px = 4;
  EXPECT_NE(p.validate().error().find("box_size_px"), std::string::npos);
  p = PixelToPixelParams{};
  p.max_radius_px = 1.0;
  EXPECT_NE(p.validate().error().find("max_radius_px"), std::string::npos);
  p = PixelToPixelParams{};
  p.min_score = 2.0;
  EXPECT_NE(p.validate().error().find("min_score"), std::string::npos);
  p = PixelToPixelParams{};
  p.isolate_max_points_factor = 0.5;
  EXPECT_NE(p.validate().error().find("isolate_max_points_factor"), std::string::npos);
  p = PixelToPixelParams{};
  p.refine_params.first_band_px = 0.0;
  EXPECT_NE(p.validate().error().find("refine_params.first_band_px"), std::string::npos);
  p = PixelToPixelParams{};
  p.refine_params.robust_fit_floor_px = std::nan("");
  EXPECT_NE(p.validate().error().find("refine_params.robust_fit_floor_px"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::ball_detector

namespace stereoball::ball_detector {
namespace {

// An orange ball held in a hand, as on the real rig's photographs: shaded (lit from the upper
// left), crossed by black seams that run to its outline, a quarter of its outline hidden by a
// skin-coloured hand whose fingers reach over the ball, on a textured wall.
cv::Mat ball_in_hand(cv::Size size, cv::Point2d c, double r, std::uint32_t seed) {
  cv::Mat img(size, CV_8UC3);
  cv::RNG rng(seed);
  rng.fill(img, cv::RNG::UNIFORM, cv::Scalar(120, 125, 130), cv::Scalar(160, 165, 170));
  cv::GaussianBlur(img, img, {0, 0}, 2.0);
  const int s = 16;  // sub-pixel drawing (shift 4)
  auto P = [&](double x, double y) { return cv::Point(cvRound(x * s), cvRound(y * s)); };
  // Shading: concentric discs darkening toward the lower right.
  for (int i = 0; i < 12; ++i) {
    const double f = 1.0 - i / 12.0;
    const double k = 0.55 + 0.45 * (1.0 - f);
    cv::circle(img, P(c.x - 0.25 * r * (1.0 - f), c.y - 0.25 * r * (1.0 - f)), cvRound(f * r * s),
               cv::Scalar(30 * k, 95 * k, 215 * k), cv::FILLED, cv::LINE_AA, 4);
  }
  // Keep the outline where it is: shading discs stay inside it.
  cv::Mat mask(size, CV_8UC1, cv::Scalar(0));
  cv::circle(mask, P(c.x, c.y), cvRound(r * s), cv::Scalar(255), cv::FILLED, cv::LINE_AA, 4);
  cv::Mat ball = img.clone();
  // Seams: a horizontal and a vertical great circle and two side curves, 3 px black, all
  // meeting the outline.
  const cv::Scalar seam(25, 25, 30);
  cv::line(ball, P(c.x - r, c.y + 0.1 * r), P(c.x + r, c.y - 0.1 * r), seam, 3, cv::LINE_AA, 4);
  cv::ellipse(ball, P(c.x, c.y), cv::Size(cvRound(0.3 * r * s), cvRound(r * s)), 0, 0, 360, seam, 3,
              cv::LINE_AA, 4);
  cv::ellipse(ball, P(c.x - 1.2 * r, c.y), cv::Size(cvRound(0.8 * r * s), cvRound(0.95 * r * s)), 0,
              -70, 70, seam, 3, cv::LINE_AA, 4);
  cv::ellipse(ball, P(c.x + 1.2 * r, c.y), cv::Size(cvRound(0.8 * r * s), cvRound(0.95 * r * s)), 0,
              110, 250, seam, 3, cv::LINE_AA, 4);
  ball.copyTo(img, mask);
  // The hand: a palm below-right of the ball hiding the quarter of its outline between 0 and
  // 90 degrees (image y down), and three fingers reaching over the ball from it.
  const cv::Scalar skin(120, 150, 205);
  std::vector<cv::Point> palm = {P(c.x + 0.25 * r, c.y + 1.6 * r), P(c.x + 1.6 * r, c.y + 1.6 * r),
                                 P(c.x + 1.6 * r, c.y + 0.2 * r), P(c.x + 0.9 * r, c.y + 0.45 * r),
                                 P(c.x + 0.45 * r, c.y + 0.9 * r)};
  cv::fillConvexPoly(img, palm, skin, cv::LINE_AA, 4);
  for (const double a : {0.15, 0.55, 0.95}) {
    const double t = a * CV_PI / 2.0;
    cv::line(img, P(c.x + 1.3 * r * std::cos(t), c.y + 1.3 * r * std::sin(t)),
             P(c.x + 0.55 * r * std::cos(t), c.y + 0.55 * r * std::sin(t)), skin, cvRound(0.16 * r),
             cv::LINE_AA, 4);
  }
  return with_sensor_noise(img, static_cast<int>(seed), 2.0);
}

// The stereo node's detector settings (config/ball_detector.yaml p2p:, input colour).
PixelToPixelParams node_like() {
  PixelToPixelParams p;
  p.k_values = {3, 5};
  p.max_radius_px = 250.0;
  p.refine_params.clutter_ring_per_radius = 0.1;
  p.refine_params.clutter_min_radius_px = 30.0;
  p.edge.colour = true;
  return p;
}

TEST(PixelToPixel, GivenABallInAHandWithAHiddenQuarterAndCrossingSeamsThenItsOutlineIsFound) {
  // Given balls of 35-90 px radius held in a hand that hides a quarter of the outline, crossed
  // by black seams, on a textured wall
  PixelToPixelDetector det(node_like());
  int found = 0, tried = 0;
  for (const double r : {35.0, 60.0, 90.0}) {
    for (std::uint32_t seed = 1; seed <= 2; ++seed) {
      const cv::Point2d c(300.0 + 3.3 * seed, 250.0 - 1.7 * seed);
      // When the detector runs on the image
      const auto circles = det.detect(ball_in_hand({640, 480}, c, r, seed));
      ++tried;
      // Then the best circle is the ball's outline: centre within 0.1 r, radius within 8 %
      const bool hit = !circles.empty() && centre_error(circles[0], {c.x, c.y, r, 1.0}) < 0.1 * r &&
                       std::abs(circles[0].radius_px - r) < 0.08 * r;
      found += hit;
      if (!hit && !circles.empty())
        ADD_FAILURE() << "r " << r << " seed " << seed << ": best (" << circles[0].x_px << ", "
                      << circles[0].y_px << ") r " << circles[0].radius_px << " score "
                      << circles[0].score;
      if (circles.empty()) ADD_FAILURE() << "r " << r << " seed " << seed << ": nothing";
    }
  }
  EXPECT_EQ(found, tried);
}

}  // namespace
}  // namespace stereoball::ball_detector
