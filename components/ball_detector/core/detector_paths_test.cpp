// The detector's searches against plain references: redetect vs detect (and its parts run
// apart, in any order), the accumulator store vs a fresh detector, and circles_from_votes
// independent of the order its voters come in. The primitives' checks are in
// voting_paths_test.cpp (peaks, rays, orientation planes), fit_paths_test.cpp (solve, fit) and
// outline_paths_test.cpp (outline points, coverage, radius, refinement).
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <optional>
#include <random>
#include <vector>

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"
#include "ball_detector/core/synthetic.hpp"
#include "ball_detector/core/voting.hpp"

namespace stereoball::ball_detector {
namespace {

using test::expect_same_circles;

TEST(Redetect, GivenBandsOfRadiiThenRedetectFindsWhatDetectWithTheSameThresholdsFinds) {
  // Given real colour images, each detected once over the whole radius range
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector once(PixelToPixelParams{}), again(PixelToPixelParams{});
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    const cv::Mat& bgr = images[i];
    once.detect(bgr);
    const EdgeThresholds thresholds = thresholds_of(once.edge_map());
    for (const RadiusRange radii : {RadiusRange{4, 11}, RadiusRange{9, 28}, RadiusRange{25, 70}}) {
      // When each band is searched by redetect (no edge step) and by detect with the thresholds
      const auto reused = once.redetect(SearchHints{radii});
      const auto fresh = again.detect(bgr, thresholds, SearchHints{radii});
      // Then the circles are the same
      ASSERT_EQ(reused.size(), fresh.size());
      for (std::size_t i = 0; i < reused.size(); ++i) {
        EXPECT_EQ(reused[i].x_px, fresh[i].x_px);
        EXPECT_EQ(reused[i].y_px, fresh[i].y_px);
        EXPECT_EQ(reused[i].radius_px, fresh[i].radius_px);
        EXPECT_EQ(reused[i].score, fresh[i].score);
      }
      circles += static_cast<int>(reused.size());
    }
  }
  EXPECT_GT(circles, 0);
}

TEST(Redetect, GivenASecondDetectorThenRedetectFromFindsWhatTheSourcesRedetectFinds) {
  // Given real colour images detected once by a source detector
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector source(PixelToPixelParams{}), reader(PixelToPixelParams{});
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    source.detect(images[i]);
    for (const RadiusRange radii :
         {RadiusRange{4, 11}, RadiusRange{25, 70}, RadiusRange{60, 160}}) {
      // When another detector searches a band on the source's lines, and the source itself
      const auto borrowed = reader.redetect_from(source, SearchHints{radii});
      const auto own = source.redetect(SearchHints{radii});
      // Then the circles are the same, bit for bit
      expect_same_circles(borrowed, own);
      circles += static_cast<int>(own.size());
    }
  }
  EXPECT_GT(circles, 0);
  // And a source that has seen no valid image lends nothing
  PixelToPixelDetector fresh(PixelToPixelParams{});
  EXPECT_TRUE(reader.redetect_from(fresh, SearchHints{}).empty());
}

TEST(Redetect, GivenDetectInTwoHalvesThenTheSameCirclesAndBandsCanBeReadBetween) {
  // Given real colour images, each voted on by one detector and detected whole by another
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector halves(PixelToPixelParams{}), whole(PixelToPixelParams{}),
      band(PixelToPixelParams{}), band_after(PixelToPixelParams{});
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    ASSERT_TRUE(halves.cast_votes(images[i]));
    // When a band is searched from the votes before the second half runs, and after it
    const auto early = band.redetect_from(halves, SearchHints{RadiusRange{9, 28}});
    const auto found = halves.circles_of_votes();
    const auto late = band_after.redetect_from(halves, SearchHints{RadiusRange{9, 28}});
    // Then the halves find what detect() finds
    expect_same_circles(found, whole.detect(images[i]));
    // And the band found the same before and after the second half
    expect_same_circles(early, late);
    circles += static_cast<int>(found.size());
  }
  EXPECT_GT(circles, 0);
  // And an invalid image casts no votes and has no circles
  EXPECT_FALSE(halves.cast_votes(cv::Mat()));
  EXPECT_EQ(halves.find_peaks_of_votes(), 0);
  EXPECT_TRUE(halves.circles_of_votes().empty());
}

TEST(Redetect, GivenPeaksRefinedOneByOneInReverseThenTheSameCirclesAsCirclesOfVotes) {
  // Given real colour images voted on by two detectors
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector parts(PixelToPixelParams{}), whole(PixelToPixelParams{});
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    ASSERT_TRUE(parts.cast_votes(images[i]));
    ASSERT_TRUE(whole.cast_votes(images[i]));
    // When one refines its peaks one by one, last first (as tasks may finish), and selects
    const int n = parts.find_peaks_of_votes();
    std::vector<PeakCircles> per_peak(static_cast<std::size_t>(n));
    for (int p = n - 1; p >= 0; --p) per_peak[static_cast<std::size_t>(p)] = parts.refine_peak(p);
    const auto found = parts.select_circles(per_peak);
    // Then it keeps exactly what the other's circles_of_votes keeps
    expect_same_circles(found, whole.circles_of_votes());
    circles += static_cast<int>(found.size());
  }
  EXPECT_GT(circles, 0);
  // And a peak index out of range refines to nothing
  EXPECT_TRUE(parts.refine_peak(-1).empty());
  EXPECT_TRUE(parts.refine_peak(1000).empty());
}

TEST(Redetect, GivenABandsPeaksRefinedOneByOneThenTheSameCirclesAsRedetectFrom) {
  // Given real colour images detected by a source, and two band detectors reading its lines
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector source(PixelToPixelParams{}), parts(PixelToPixelParams{}),
      whole(PixelToPixelParams{});
  int circles = 0, peaks = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    source.detect(images[i]);
    for (const RadiusRange radii :
         {RadiusRange{4, 11}, RadiusRange{25, 70}, RadiusRange{60, 160}}) {
      // When one votes a band and refines its peaks one by one, last first, and selects
      const std::optional<int> n = parts.peaks_from(source, SearchHints{radii});
      ASSERT_TRUE(n.has_value());
      std::vector<PeakCircles> per_peak(static_cast<std::size_t>(*n));
      for (int p = *n - 1; p >= 0; --p)
        per_peak[static_cast<std::size_t>(p)] = parts.refine_peak(p);
      const auto found = parts.select_circles(per_peak);
      // Then it keeps exactly what the other's redetect_from keeps
      expect_same_circles(found, whole.redetect_from(source, SearchHints{radii}));
      circles += static_cast<int>(found.size());
      peaks += *n;
    }
  }
  EXPECT_GT(circles, 0);
  EXPECT_GT(peaks, circles);
  // And a source without an image, or an empty radius range, gives no peaks to refine
  PixelToPixelDetector fresh(PixelToPixelParams{});
  EXPECT_FALSE(parts.peaks_from(fresh, SearchHints{}).has_value());
  EXPECT_FALSE(parts.peaks_from(source, SearchHints{RadiusRange{20, 20}}).has_value());
}

TEST(Redetect, GivenEdgesFoundFirstThenVotingOnThemFindsWhatCastVotesFinds) {
  // Given real colour images: one detector finds their edges alone (as the coarse try does),
  // refines a seed on them, then votes on those edges; another casts its votes on the image
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector reused(PixelToPixelParams{}), fresh(PixelToPixelParams{});
  EXPECT_FALSE(reused.cast_votes_on_last_edges()) << "no image yet: no edges to vote on";
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 6); ++i) {
    ASSERT_TRUE(reused.find_edges(images[i]));
    const Circle seed{images[i].cols / 2.0, images[i].rows / 2.0, 20.0, 0.0};
    (void)reused.refine_seeds({&seed, 1});
    // When the first votes on its last edges and the other casts its votes
    ASSERT_TRUE(reused.cast_votes_on_last_edges());
    ASSERT_TRUE(fresh.cast_votes(images[i]));
    // Then both accumulators and circles are the same, bit for bit
    EXPECT_EQ(cv::norm(reused.raw_accumulator(), fresh.raw_accumulator(), cv::NORM_INF), 0.0);
    const auto found = reused.circles_of_votes();
    expect_same_circles(found, fresh.circles_of_votes());
    circles += static_cast<int>(found.size());
  }
  EXPECT_GT(circles, 0);
  // And after an invalid image there are no edges to vote on
  EXPECT_FALSE(reused.find_edges(cv::Mat()));
  EXPECT_FALSE(reused.cast_votes_on_last_edges());
}

// The maps of two detectors are equal cell for cell.
bool same_map(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

TEST(AccumulatorStore, GivenSearchesWhoseMarginsChangeThenEachEqualsAFreshDetectorsSearch) {
  // Given real colour images and one detector that searches them with margins that grow,
  // shrink and repeat (its vote maps change size from search to search)
  const auto images = real_colours();
  ASSERT_FALSE(images.empty());
  PixelToPixelDetector reused(PixelToPixelParams{});
  int circles = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(images.size(), 3); ++i) {
    const cv::Mat& bgr = images[i];
    PixelToPixelDetector probe(PixelToPixelParams{});
    probe.detect(bgr);
    const EdgeThresholds thresholds = thresholds_of(probe.edge_map());
    cv::Mat earlier, earlier_copy;  // a smoothed map handed out by the previous search
    for (const int margin : {0, 40, 10, 80, 80, 0}) {
      SearchHints hints{RadiusRange{4, 90}};
      hints.centre_margin_px = margin;
      // When the reused detector and a fresh one search with the same hints
      PixelToPixelDetector fresh(PixelToPixelParams{});
      const auto ours = reused.detect(bgr, thresholds, hints);
      const auto reference = fresh.detect(bgr, thresholds, hints);
      // Then the circles and both vote maps are the same
      expect_same_circles(ours, reference);
      EXPECT_TRUE(same_map(reused.raw_accumulator(), fresh.raw_accumulator())) << margin;
      EXPECT_TRUE(same_map(reused.diagnostics()->accumulator, fresh.diagnostics()->accumulator))
          << margin;
      // And a map handed out by an earlier search of another size kept its values
      if (!earlier.empty() && earlier.size() != reused.diagnostics()->accumulator.size()) {
        EXPECT_TRUE(same_map(earlier, earlier_copy)) << margin;
      }
      earlier = reused.diagnostics()->accumulator;
      earlier_copy = earlier.clone();
      circles += static_cast<int>(ours.size());
    }
  }
  EXPECT_GT(circles, 0);
}

TEST(Redetect, GivenNoImageOrAnInvalidOneThenItFindsNothing) {
  // Given a detector that has seen no image, then an invalid one after a valid one
  PixelToPixelDetector detector(PixelToPixelParams{});
  EXPECT_TRUE(detector.redetect(SearchHints{}).empty());
  const auto scene = make_scene(SceneKind::kPlain, cv::Size(320, 240), 3);
  EXPECT_FALSE(detector.detect(scene.image).empty());
  detector.detect(cv::Mat());
  // Then redetect does not reuse the old edge map
  EXPECT_TRUE(detector.redetect(SearchHints{}).empty());
}

TEST(CirclesFromVotes, GivenTheSameVotersInAnyOrderThenTheSameCirclesAreFound) {
  // Given a synthetic scene with several balls and the voters P2P cast on it
  const auto suite = make_suite(cv::Size(640, 480), 1, 4);
  const auto several = std::find_if(suite.begin(), suite.end(),
                                    [](const SyntheticScene& s) { return s.truth.size() >= 2; });
  ASSERT_NE(several, suite.end());
  PixelToPixelParams p;
  p.k_values = {3, 5, 8};  // several raster passes: the voters come in several runs
  p.min_radius_px = 12;
  p.max_radius_px = 96;
  PixelToPixelDetector detector(p);
  const auto found = detector.detect(several->image);
  ASSERT_GE(found.size(), 2u);
  const cv::Mat& smoothed = detector.diagnostics()->accumulator;
  double max_v = 0.0;
  cv::minMaxLoc(smoothed, nullptr, &max_v);
  const auto peaks = find_peaks(smoothed, static_cast<float>(0.15 * max_v), 10.0, 16);
  CandidateOptions options;
  options.min_radius_px = p.min_radius_px;
  options.max_radius_px = p.max_radius_px;
  const auto in_order = circles_from_votes(detector.edge_map(), detector.voters(), peaks, options);
  // When the voters are shuffled (no raster order left to exploit)
  auto shuffled = detector.voters();
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937(1));
  const auto any_order = circles_from_votes(detector.edge_map(), shuffled, peaks, options);
  // Then the circles agree (sums in another order: equal to rounding)
  ASSERT_EQ(in_order.size(), any_order.size());
  ASSERT_GE(in_order.size(), 2u);
  for (size_t i = 0; i < in_order.size(); ++i) {
    EXPECT_NEAR(in_order[i].x_px, any_order[i].x_px, 1e-6);
    EXPECT_NEAR(in_order[i].y_px, any_order[i].y_px, 1e-6);
    EXPECT_NEAR(in_order[i].radius_px, any_order[i].radius_px, 1e-6);
    EXPECT_NEAR(in_order[i].score, any_order[i].score, 1e-9);
  }
}

}  // namespace
}  // namespace stereoball::ball_detector
