// Pixel-to-Pixel's multi-scale search (PixelToPixelParams::fine_below_radius_px): small circles
// at full resolution beside the coarse-to-fine search of the large ones.

#include "ball_detector/core/circle_labels.hpp"
#include "ball_detector/core/evaluation.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <variant>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// Labelled circles overlapped by a found one with IoU >= 0.8.
int found_of(const std::vector<Circle>& found, const std::vector<Circle>& truth) {
  return match_circles(found, truth, 0.8).true_positives;
}

PixelToPixelParams coarse_params(double min_radius_px, double max_radius_px) {
  PixelToPixelParams p;
  p.k_values = {3, 5};
  p.min_radius_px = min_radius_px;
  p.max_radius_px = max_radius_px;
  p.min_separation_px = 12.0;
  p.max_circles = 40;
  p.max_peaks_examined = 80;
  p.coarse_to_fine = true;
  return p;
}

// A 640x480 grey scene: a large disc and a row of small ones, each darker than the background.
struct SmallAndLarge {
  cv::Mat image;
  std::vector<Circle> small, large;
};

SmallAndLarge small_and_large_scene(double small_radius_px) {
  SmallAndLarge s;
  s.image = cv::Mat(480, 640, CV_8UC3, cv::Scalar(200, 200, 200));
  s.large.push_back({460.0, 250.0, 90.0, 0.0});
  for (int i = 0; i < 8; ++i)
    s.small.push_back({40.0 + 40.0 * i, 80.0 + 45.0 * (i % 3), small_radius_px, 0.0});
  // Drawn at 1/16 pixel (shift 4) so the centres and radii are the ones labelled.
  auto draw = [&](const Circle& c) {
    cv::circle(s.image, cv::Point(cvRound(c.x_px * 16), cvRound(c.y_px * 16)),
               cvRound(c.radius_px * 16), cv::Scalar(60, 60, 60), cv::FILLED, cv::LINE_AA, 4);
  };
  for (const Circle& c : s.large) draw(c);
  for (const Circle& c : s.small) draw(c);
  // A camera's blur and noise: the halved image's small discs are then faint few-pixel blobs.
  cv::GaussianBlur(s.image, s.image, cv::Size(5, 5), 1.2);
  cv::Mat noise(s.image.size(), CV_16SC3);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, 6.0);
  cv::Mat image16;
  s.image.convertTo(image16, CV_16SC3);
  image16 += noise;
  image16.convertTo(s.image, CV_8UC3);
  return s;
}

TEST(PixelToPixelMultiScale, GivenSmallAndLargeCirclesThenBothSizesAreFound) {
  // Given 4.5 px discs and a 90 px disc, and the coarse-to-fine search alone or with the radii
  // below 10 px searched at full resolution
  const SmallAndLarge scene = small_and_large_scene(4.5);
  PixelToPixelParams p = coarse_params(3.5, 120.0);
  PixelToPixelDetector coarse_only(p);
  p.fine_below_radius_px = 10.0;
  PixelToPixelDetector multi_scale(p);
  // When both search the scene
  const auto coarse_found = coarse_only.detect(scene.image);
  const auto multi_found = multi_scale.detect(scene.image);
  // Then the multi-scale search finds every small disc and still the large one, and more small
  // ones than the halved image gives
  EXPECT_EQ(found_of(multi_found, scene.small), 8);
  EXPECT_EQ(found_of(multi_found, scene.large), 1);
  EXPECT_EQ(found_of(coarse_found, scene.large), 1);
  EXPECT_LT(found_of(coarse_found, scene.small), found_of(multi_found, scene.small));
}

TEST(PixelToPixelMultiScale, GivenEveryRadiusBelowTheSplitThenOnlyTheFullResolutionSearchRuns) {
  // Given a split above the largest radius searched
  const SmallAndLarge scene = small_and_large_scene(8.0);
  PixelToPixelParams p = coarse_params(5.0, 20.0);
  p.fine_below_radius_px = 30.0;
  PixelToPixelDetector det(p);
  // When it searches the scene
  const auto found = det.detect(scene.image);
  // Then the small discs are found and nothing larger than the largest radius is returned
  EXPECT_EQ(found_of(found, scene.small), 8);
  for (const Circle& c : found) EXPECT_LE(c.radius_px, 20.0);
}

// A labelled photograph of tests/data/circles: its image and circles (empty image if unreadable).
struct Labelled {
  cv::Mat image;
  CircleLabels labels;
};

Labelled load_labelled(const std::string& stem) {
  const std::string dir = std::string(SB_SOURCE_DIR) + "/tests/data/circles/";
  std::ifstream in(dir + stem + ".circles");
  std::stringstream text;
  text << in.rdbuf();
  auto parsed = parse_circle_labels(text.str(), stem + ".circles");
  if (!std::holds_alternative<CircleLabels>(parsed)) return {};
  Labelled out{cv::Mat(), std::get<CircleLabels>(parsed)};
  out.image = cv::imread(std::string(SB_SOURCE_DIR) + "/" + out.labels.image_path);
  return out;
}

// Every circle of a has one in b within tol_px in centre and radius (and as many circles).
void expect_same_circles(const std::vector<Circle>& a, const std::vector<Circle>& b,
                         double tol_px) {
  ASSERT_EQ(a.size(), b.size());
  for (const Circle& c : a)
    EXPECT_TRUE(std::any_of(b.begin(), b.end(),
                            [&](const Circle& d) {
                              return std::abs(c.x_px - d.x_px) <= tol_px &&
                                     std::abs(c.y_px - d.y_px) <= tol_px &&
                                     std::abs(c.radius_px - d.radius_px) <= tol_px;
                            }))
        << "circle " << c.x_px << " " << c.y_px << " r " << c.radius_px;
}

// The bench's chosen multi-scale setting on a labelled photograph (tools/bench-detect).
PixelToPixelParams photo_multi_scale(const Labelled& photo) {
  const double side = std::min(photo.image.cols, photo.image.rows);
  PixelToPixelParams p =
      coarse_params(photo.labels.min_radius_px.value_or(0.025 * side), 0.2 * side);
  p.min_separation_px = 0.04 * side;
  p.max_circles = 100;
  p.max_peaks_examined = 50;
  p.fine_below_radius_px = 2.0 * p.min_radius_px;
  p.fine_give_up = true;
  p.min_score = 0.55;
  p.refine_params.band_per_radius = 0.035;
  p.refine_params.clutter_ring_per_radius = 0.2;
  return p;
}

TEST(PixelToPixelMultiScale, GivenTheCoarsePeakCapAtItsImpliedCountThenTheSameCircles) {
  // Given the synthetic scene and the board photograph, each searched with the halved image's
  // peaks uncapped and capped at the count it examines anyway (max(peaks, circles))
  const SmallAndLarge scene = small_and_large_scene(4.5);
  const Labelled board = load_labelled("board");
  ASSERT_FALSE(board.image.empty());
  for (const auto& [image, params] : {std::pair{scene.image, coarse_params(3.5, 120.0)},
                                      std::pair{board.image, photo_multi_scale(board)}}) {
    PixelToPixelParams p = params;
    PixelToPixelDetector uncapped(p);
    p.coarse_max_peaks_examined = std::max(p.max_peaks_examined, p.max_circles);
    PixelToPixelDetector capped(p);
    // When both search it
    const auto a = uncapped.detect(image);
    const auto b = capped.detect(image);
    // Then they return the same circles, bit for bit
    test::expect_same_circles(a, b);
  }
}

TEST(PixelToPixelMultiScale, GivenAFewCoarsePeaksThenAtMostThatManyLargeCircles) {
  // Given the synthetic scene searched coarse to fine with the halved image's peaks capped at 2
  const SmallAndLarge scene = small_and_large_scene(8.0);
  PixelToPixelParams p = coarse_params(5.0, 120.0);
  p.coarse_max_peaks_examined = 2;
  PixelToPixelDetector det(p);
  // When it searches the scene
  const auto found = det.detect(scene.image);
  // Then at most two circles come back, the large disc among them
  EXPECT_LE(found.size(), 2u);
  EXPECT_EQ(found_of(found, scene.large), 1);
  // And the cap is checked
  p.coarse_max_peaks_examined = 1001;
  EXPECT_NE(p.validate().error().find("coarse_max_peaks_examined"), std::string::npos);
}

TEST(PixelToPixelMultiScale, GivenSharedEdgesThenTheCirclesOfTheWindowsOwnEdges) {
  // Given the synthetic scene and the board photograph, each searched multi-scale with the large
  // radii refined on their windows' own edge maps and on the small search's whole-image map
  SmallAndLarge scene = small_and_large_scene(4.5);
  PixelToPixelParams synthetic = coarse_params(3.5, 120.0);
  synthetic.fine_below_radius_px = 10.0;
  const Labelled board = load_labelled("board");
  ASSERT_FALSE(board.image.empty());
  for (const auto& [image, params, truth] :
       {std::tuple{scene.image, synthetic, scene.large},
        std::tuple{board.image, photo_multi_scale(board), board.labels.circles}}) {
    PixelToPixelParams p = params;
    PixelToPixelDetector own(p);
    p.fine_shared_edges = true;
    PixelToPixelDetector shared(p);
    // When both search it
    const auto a = own.detect(image);
    const auto b = shared.detect(image);
    // Then they find the same labelled circles, at the same places within a tenth of a pixel
    EXPECT_EQ(found_of(a, truth), found_of(b, truth));
    EXPECT_GE(found_of(b, truth), 1);
    expect_same_circles(a, b, 0.1);
  }
}

TEST(PixelToPixelMultiScale, GivenTheBoardPhotographThenItsSmallPadsAreFound) {
  // Given board.jpg (tune split: 19 round pads of 8.4-17.1 px labelled down to 8 px) and the
  // benchmark's search range for it, coarse to fine alone or with radii below 2 x 8 px searched
  // at full resolution
  const Labelled board = load_labelled("board");
  ASSERT_FALSE(board.image.empty());
  ASSERT_TRUE(board.labels.min_radius_px.has_value());
  PixelToPixelParams p = coarse_params(*board.labels.min_radius_px, 0.2 * board.image.rows);
  p.min_separation_px = 0.04 * board.image.rows;
  p.max_circles = 100;
  p.max_peaks_examined = 200;
  PixelToPixelDetector coarse_only(p);
  p.fine_below_radius_px = 2.0 * *board.labels.min_radius_px;
  PixelToPixelDetector multi_scale(p);
  // When both search the photograph
  const int coarse_found = found_of(coarse_only.detect(board.image), board.labels.circles);
  const int multi_found = found_of(multi_scale.detect(board.image), board.labels.circles);
  // Then the multi-scale search finds more of the pads, and two thirds of them
  EXPECT_GT(multi_found, coarse_found);
  EXPECT_GE(multi_found, 13);  // two thirds of 19
}

TEST(PixelToPixelMultiScale, GivenBadFineSettingsThenValidateNamesThem) {
  PixelToPixelParams p;
  p.fine_below_radius_px = -1.0;
  EXPECT_NE(p.validate().error().find("fine_below_radius_px"), std::string::npos);
  p.fine_below_radius_px = 12.0;
  p.fine_k_values = {0};
  EXPECT_NE(p.validate().error().find("fine_k_values"), std::string::npos);
  p.fine_k_values = {};
  EXPECT_NE(p.validate().error().find("fine_k_values"), std::string::npos);
  p.fine_k_values = {2, 3};
  EXPECT_TRUE(p.validate());
  p.fine_max_peaks_examined = -1;
  EXPECT_NE(p.validate().error().find("fine_max_peaks_examined"), std::string::npos);
  p.fine_max_peaks_examined = 1001;
  EXPECT_NE(p.validate().error().find("fine_max_peaks_examined"), std::string::npos);
  p.fine_max_peaks_examined = 25;
  EXPECT_TRUE(p.validate());
  p.fine_stop_after_missed_peaks = -1;
  EXPECT_NE(p.validate().error().find("fine_stop_after_missed_peaks"), std::string::npos);
  p.fine_stop_after_missed_peaks = 3;
  p.stop_after_missed_peaks = 1001;
  EXPECT_NE(p.validate().error().find("stop_after_missed_peaks"), std::string::npos);
  p.stop_after_missed_peaks = 0;
  EXPECT_TRUE(p.validate());
}

TEST(PixelToPixelMultiScale, GivenAStopAfterMissedPeaksThenOnlyTheSmallSearchStopsAndFindsAll) {
  // Given 4.5 px discs and a 90 px disc, and the multi-scale search whose small-radius search
  // stops after 3 peaks in a row give no circle
  const SmallAndLarge scene = small_and_large_scene(4.5);
  PixelToPixelParams p = coarse_params(3.5, 120.0);
  p.fine_below_radius_px = 10.0;
  p.fine_stop_after_missed_peaks = 3;
  // When its searches are derived and it searches the scene
  const PixelToPixelParams small = p.small_circle_search();
  const PixelToPixelParams large = p.large_circle_search();
  PixelToPixelDetector det(p);
  const auto found = det.detect(scene.image);
  // Then only the small-radius search stops early, and every disc is still found (the discs'
  // peaks are the strongest)
  EXPECT_EQ(small.stop_after_missed_peaks, 3);
  EXPECT_EQ(large.stop_after_missed_peaks, 0);
  EXPECT_EQ(found_of(found, scene.small), 8);
  EXPECT_EQ(found_of(found, scene.large), 1);
}

TEST(PixelToPixelMultiScale, GivenCheaperFineSettingsThenOnlyTheSmallRadiusSearchChanges) {
  // Given the multi-scale search with the small radii's peaks capped and their arc isolation off
  PixelToPixelParams p = coarse_params(3.5, 120.0);
  p.fine_below_radius_px = 10.0;
  p.fine_max_peaks_examined = 25;
  p.fine_isolate_arc = false;
  // When its two searches are derived
  const PixelToPixelParams small = p.small_circle_search();
  const PixelToPixelParams large = p.large_circle_search();
  // Then the full-resolution search examines 25 peaks, keeps 25 circles and does not isolate
  // arcs, and the coarse-to-fine search keeps the detector's own values
  EXPECT_EQ(small.max_peaks_examined, 25);
  EXPECT_EQ(small.max_circles, 25);
  EXPECT_FALSE(small.isolate_arc);
  EXPECT_EQ(large.max_peaks_examined, 80);
  EXPECT_EQ(large.max_circles, 40);
  EXPECT_TRUE(large.isolate_arc);
  // And giving up on weak candidates sets the small search's first-round floor to min_score
  // (no rescue below it), the large search's untouched
  p.fine_give_up = true;
  EXPECT_EQ(p.small_circle_search().refine_params.give_up_below, p.min_score);
  EXPECT_GE(p.small_circle_search().rescue_weak_from, p.min_score);
  EXPECT_EQ(p.large_circle_search().refine_params.give_up_below,
            PixelToPixelParams{}.refine_params.give_up_below);
  p.fine_give_up = false;
  // And with both off the full-resolution search is the detector's own
  p.fine_max_peaks_examined = 0;
  p.fine_isolate_arc = true;
  EXPECT_EQ(p.small_circle_search().max_peaks_examined, 80);
  EXPECT_EQ(p.small_circle_search().max_circles, 40);
  EXPECT_TRUE(p.small_circle_search().isolate_arc);
}

TEST(PixelToPixelMultiScale, GivenCheaperFineSettingsThenTheyChangeOnlyTheSmallCirclesFound) {
  // Given 4.5 px discs and a 90 px disc, and the multi-scale search without arc isolation in its
  // full-resolution search, then also with at most 4 peaks examined there, then instead giving
  // up on weak candidates there
  const SmallAndLarge scene = small_and_large_scene(4.5);
  PixelToPixelParams p = coarse_params(3.5, 120.0);
  p.fine_below_radius_px = 10.0;
  p.fine_isolate_arc = false;
  PixelToPixelDetector no_isolation(p);
  p.fine_max_peaks_examined = 4;
  PixelToPixelDetector capped(p);
  p.fine_max_peaks_examined = 0;
  p.fine_give_up = true;
  PixelToPixelDetector giving_up(p);
  // When they search the scene
  const auto found = no_isolation.detect(scene.image);
  const auto capped_found = capped.detect(scene.image);
  const auto given_up_found = giving_up.detect(scene.image);
  // Then without isolation every small disc and the large one are found; with the cap at most
  // 4 circles below the split, and still the large disc
  EXPECT_EQ(found_of(found, scene.small), 8);
  EXPECT_EQ(found_of(found, scene.large), 1);
  int small_capped = 0;
  for (const Circle& c : capped_found) small_capped += c.radius_px < 10.0;
  EXPECT_LE(small_capped, 4);
  EXPECT_GE(found_of(capped_found, scene.small), 1);
  EXPECT_EQ(found_of(capped_found, scene.large), 1);
  // And giving up on weak candidates still finds every disc
  EXPECT_EQ(found_of(given_up_found, scene.small), 8);
  EXPECT_EQ(found_of(given_up_found, scene.large), 1);
}

}  // namespace
}  // namespace stereoball::ball_detector
