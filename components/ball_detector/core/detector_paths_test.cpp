// The detector's searches and fits against plain references: redetect vs detect (and its parts
// run apart, in any order), the accumulator store vs a fresh detector, find_peaks vs a
// brute-force scan, plot_ray vs a bounds test per cell, estimate_radius vs a scan of every edge
// pixel, angular_coverage_in_frame vs every sector tested, the orientation planes vs points set
// one by one, circles_from_votes independent of the order its voters come in, solve_3x3 vs
// cv::solve, fit_circle and gather_outline_points vs their plain arithmetic, and refine_circle's
// reused scan vs a fresh one.

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <iterator>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "ball_detector/core/canny.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/core/p2p_rules.hpp"
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

std::vector<Peak> brute_force_peaks(const cv::Mat& m, int floor_value) {
  std::vector<Peak> out;
  for (int y = 1; y < m.rows - 1; ++y)
    for (int x = 1; x < m.cols - 1; ++x) {
      const int v = m.at<int>(y, x);
      if (v < floor_value) continue;
      bool peak = true;
      for (int dy = -1; dy <= 1 && peak; ++dy)
        for (int dx = -1; dx <= 1 && peak; ++dx) {
          if (!dx && !dy) continue;
          const int u = m.at<int>(y + dy, x + dx);
          // earlier in raster order: strictly greater; later: greater or equal
          const bool earlier = dy < 0 || (dy == 0 && dx < 0);
          peak = earlier ? v > u : v >= u;
        }
      if (peak) out.push_back({x, y, static_cast<float>(v)});
    }
  std::stable_sort(out.begin(), out.end(),
                   [](const Peak& a, const Peak& b) { return a.value > b.value; });
  return out;
}

void expect_brute_force_peaks(const cv::Mat& smoothed, int floor_value,
                              const std::vector<Peak>& peaks) {
  const auto expected = brute_force_peaks(smoothed, floor_value);
  ASSERT_EQ(peaks.size(), expected.size());
  for (size_t i = 0; i < peaks.size(); ++i) {
    EXPECT_EQ(peaks[i].x, expected[i].x);
    EXPECT_EQ(peaks[i].y, expected[i].y);
    EXPECT_EQ(peaks[i].value, expected[i].value);
  }
}

TEST(FindPeaks, GivenSmoothedRandomVotesThenPeaksEqualABruteForceScan) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 20; ++trial) {
    // Given a smoothed accumulator of random votes with plateaus (small integer range)
    cv::Mat acc(97 + trial, 131 + 3 * trial, CV_16UC1);
    cv::randu(acc, 0, 4);
    cv::Mat smoothed;
    std::vector<int> row_maxima;
    box_filter(acc, 3, smoothed, row_maxima);
    const int floor_value = 10 + trial % 7;
    // When peaks are found with no separation and no limit (rows scanned for their maxima, and
    // the box filter's row maxima taken)
    const auto peaks = find_peaks(smoothed, static_cast<float>(floor_value), 0.0, 1 << 20);
    const auto given_maxima =
        find_peaks(smoothed, static_cast<float>(floor_value), 0.0, 1 << 20, row_maxima);
    // Then they are the brute-force local maxima, strongest first
    expect_brute_force_peaks(smoothed, floor_value, peaks);
    expect_brute_force_peaks(smoothed, floor_value, given_maxima);
  }
}

TEST(FindPeaks, GivenAMapWhoseRowsAreMostlyBelowTheFloorThenPeaksEqualABruteForceScan) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 20; ++trial) {
    // Given a plain scene's map: a few bands of votes (one on the first or last row that can
    // hold a peak) in rows that are otherwise empty, which the fast path skips
    cv::Mat acc = cv::Mat::zeros(90 + trial, 120 + 2 * trial, CV_16UC1);
    for (int band = 0; band < 3; ++band) {
      const int y = band == 0 ? (trial % 2 ? 1 : acc.rows - 2) : static_cast<int>(rng() % acc.rows);
      cv::randu(acc.row(y), 0, 9);
    }
    cv::Mat smoothed;
    std::vector<int> row_maxima;
    box_filter(acc, 1 + 2 * (trial % 3), smoothed, row_maxima);
    const int floor_value = 3 + trial % 5;
    // When peaks are found with no separation and no limit, the skipped rows told by the box
    // filter's row maxima too
    const auto peaks = find_peaks(smoothed, static_cast<float>(floor_value), 0.0, 1 << 20);
    const auto given_maxima =
        find_peaks(smoothed, static_cast<float>(floor_value), 0.0, 1 << 20, row_maxima);
    // Then they are the brute-force local maxima, strongest first
    expect_brute_force_peaks(smoothed, floor_value, peaks);
    expect_brute_force_peaks(smoothed, floor_value, given_maxima);
  }
}

TEST(FindPeaks, GivenMapsOfEveryWidthUpToFortyThenPeaksEqualABruteForceScan) {
  // The vector path takes eight columns at a time and the rest one by one: every width from the
  // narrowest map with an inner column up, so each remainder occurs, plateaus included.
  for (int width = 3; width <= 40; ++width) {
    // Given a smoothed map of random votes of that width
    cv::Mat acc(24, width, CV_16UC1);
    cv::randu(acc, 0, 3);
    const cv::Mat smoothed = box_filter(acc, 3);
    const int floor_value = 4 + width % 5;
    // When peaks are found with no separation and no limit
    const auto peaks = find_peaks(smoothed, static_cast<float>(floor_value), 0.0, 1 << 20);
    // Then they are the brute-force local maxima, strongest first
    expect_brute_force_peaks(smoothed, floor_value, peaks);
  }
}

// The ray plotting as it was before its bounds were counted up front: a bounds test per cell.
std::int64_t plot_ray_reference(cv::Mat& accumulator, double start_x, double start_y, double dir_x,
                                double dir_y, double t0_px, double t1_px) {
  const auto round_half_away = [](double x) { return static_cast<std::int64_t>(std::llround(x)); };
  const double norm = std::sqrt(dir_x * dir_x + dir_y * dir_y);
  if (norm <= 0.0 || t1_px < t0_px) return 0;
  const double ux = dir_x / norm, uy = dir_y / norm;
  const double sx = start_x + ux * t0_px, sy = start_y + uy * t0_px;
  const bool x_major = std::abs(ux) >= std::abs(uy);
  const double major = x_major ? ux : uy;
  const int steps = static_cast<int>((t1_px - t0_px) * std::abs(major));
  const int step = major > 0 ? 1 : -1;
  const double slope = (x_major ? uy : ux) / std::abs(major);
  int m = static_cast<int>(round_half_away(x_major ? sx : sy));
  const double minor0 = (x_major ? sy : sx) + (m - (x_major ? sx : sy)) * slope * step;
  std::int64_t minor_fp = round_half_away((minor0 + 0.5) * 65536.0);
  const std::int64_t dminor = round_half_away(slope * 65536.0);
  std::int64_t done = 0;
  for (int i = 0; i <= steps; ++i, m += step, minor_fp += dminor) {
    const int n = static_cast<int>(minor_fp >> 16);
    const int x = x_major ? m : n, y = x_major ? n : m;
    if (x < 0 || y < 0 || x >= accumulator.cols || y >= accumulator.rows) break;
    std::uint16_t& cell = accumulator.at<std::uint16_t>(y, x);
    if (cell != 0xFFFF) ++cell;
    ++done;
  }
  return done;
}

TEST(PlotRay, GivenRandomRaysInAndAroundTheMapThenCellsAndCountsEqualABoundsTestPerCell) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 40; ++trial) {
    // Given a vote map (a view into a larger one, so rows have a stride; some cells already
    // full or one short of it) and rays starting inside, on the border and outside, with the
    // detector's integer and arbitrary real directions, steep, flat and diagonal
    cv::Mat parent(70 + trial, 90 + 2 * trial, CV_16UC1);
    cv::randu(parent, 0, 3);
    cv::Mat acc = parent(cv::Rect(3, 2, parent.cols - 7, parent.rows - 5));
    cv::Mat ref_parent = parent.clone();
    cv::Mat ref = ref_parent(cv::Rect(3, 2, parent.cols - 7, parent.rows - 5));
    for (int i = 0; i < 40; ++i) {
      const cv::Point p(static_cast<int>(rng() % acc.cols), static_cast<int>(rng() % acc.rows));
      acc.at<std::uint16_t>(p) = ref.at<std::uint16_t>(p) =
          static_cast<std::uint16_t>(0xFFFE + i % 2);
    }
    cv::Mat fresh = cv::Mat::zeros(acc.size(), CV_16UC1), fresh_ref = fresh.clone();
    for (int ray = 0; ray < 400; ++ray) {
      const double x = -20.0 + unit(rng) * (acc.cols + 40);
      const double y = -20.0 + unit(rng) * (acc.rows + 40);
      double dx = static_cast<int>(rng() % 21) - 10, dy = static_cast<int>(rng() % 21) - 10;
      if (ray % 3 == 0) {
        dx = unit(rng) * 2.0 - 1.0;
        dy = unit(rng) * 2.0 - 1.0;
      }
      if (ray % 17 == 0) dy = 0.0;
      if (ray % 19 == 0) dx = 0.0;
      if (ray % 23 == 0) dx = dy;
      const double t0 = unit(rng) * 10.0, t1 = t0 + unit(rng) * 150.0 - 5.0;
      // When both plot it, and ours again without the saturation test on a map with no full
      // cell
      const auto ours = plot_ray(acc, x, y, dx, dy, t0, t1);
      const auto reference = plot_ray_reference(ref, x, y, dx, dy, t0, t1);
      const auto unsaturated = plot_ray(fresh, x, y, dx, dy, t0, t1, false);
      plot_ray_reference(fresh_ref, x, y, dx, dy, t0, t1);
      // Then the same cells got a vote, none outside the map
      ASSERT_EQ(ours, reference) << "trial " << trial << " ray " << ray;
      ASSERT_EQ(unsaturated, reference) << "trial " << trial << " ray " << ray;
    }
    ASSERT_EQ(cv::countNonZero(parent != ref_parent), 0) << "trial " << trial;
    ASSERT_EQ(cv::countNonZero(fresh != fresh_ref), 0) << "trial " << trial;
  }
}

TEST(PlotRay, GivenADirectionSetUpOnceThenEveryRayAlongItEqualsAFreshPlot) {
  std::mt19937 rng(37);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  cv::Mat once = cv::Mat::zeros(90, 120, CV_16UC1), fresh = once.clone();
  // Given every integer direction a vote line can take (|nx|, |ny| <= 62), set up once
  for (int nx = -62; nx <= 62; ++nx)
    for (int ny = -62; ny <= 62; ++ny) {
      const RayDirection dir = ray_direction(nx, ny);
      for (int ray = 0; ray < 3; ++ray) {
        // When rays from anywhere in and around the map are plotted along it
        const double x = -10.0 + unit(rng) * 140.0, y = -10.0 + unit(rng) * 110.0;
        const double t0 = unit(rng) * 10.0, t1 = t0 + unit(rng) * 80.0;
        const bool saturate = ray == 0;
        // Then each gets the cells and count of plot_ray set up afresh
        ASSERT_EQ(plot_ray(once, x, y, dir, t0, t1, saturate),
                  plot_ray(fresh, x, y, nx, ny, t0, t1, saturate))
            << nx << " " << ny << " ray " << ray;
      }
    }
  ASSERT_EQ(cv::countNonZero(once != fresh), 0);
  EXPECT_GT(cv::countNonZero(once), 0);
}

// estimate_radius written plainly: every edge pixel of the image, the same tests and rings.
std::optional<double> estimate_radius_reference(const EdgeMap& edges, double cx, double cy,
                                                double min_radius_px, double max_radius_px) {
  const int r0 = std::max(1, static_cast<int>(std::floor(min_radius_px)));
  const int r1 = static_cast<int>(std::ceil(max_radius_px));
  if (r1 <= r0) return std::nullopt;
  std::vector<int> hist(r1 + 2, 0);
  for (int y = 0; y < edges.edges.rows; ++y)
    for (int x = 0; x < edges.edges.cols; ++x) {
      if (edges.edges.at<std::uint8_t>(y, x) == 0) continue;
      const double rx = x - cx, ry = y - cy;
      const double d2 = rx * rx + ry * ry;
      const int bin = static_cast<int>(std::sqrt(d2) + 0.5);
      if (bin < r0 || bin > r1) continue;
      const double gx = edges.dx.at<short>(y, x), gy = edges.dy.at<short>(y, x);
      const double g_dot_r = gx * rx + gy * ry;
      if (g_dot_r * g_dot_r < 0.49 * (gx * gx + gy * gy) * d2) continue;
      ++hist[static_cast<std::size_t>(bin)];
    }
  double best = 0.0;
  std::optional<double> best_r;
  for (int r = r0; r <= r1; ++r) {
    const int ring = hist[static_cast<std::size_t>(r)] + hist[static_cast<std::size_t>(r - 1)] +
                     hist[static_cast<std::size_t>(r + 1)];
    if (ring >= 8 && ring / static_cast<double>(r) > best) {
      best = ring / static_cast<double>(r);
      best_r = r;
    }
  }
  return best_r;
}

TEST(EstimateRadius, GivenRealEdgeMapsAndCentresAnywhereThenTheRingEqualsAPlainScan) {
  // Given the real images' edge maps (colour edges), and centres inside, near the border and
  // outside the image, whole and fractional, with narrow and wide radius ranges
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u);
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int found = 0;
  for (const auto& image : images) {
    EdgeMap edges;
    compute_edge_map(image, EdgeParams{}, edges);
    for (int trial = 0; trial < 30; ++trial) {
      double cx = -30.0 + unit(rng) * (image.cols + 60), cy = -30.0 + unit(rng) * (image.rows + 60);
      if (trial % 2 == 0) {
        cx = std::round(cx);
        cy = std::round(cy);
      }
      const double lo = trial % 3 == 0 ? 0.5 : 4.0 + unit(rng) * 30.0;
      const double hi = lo + (trial % 4 == 0 ? 3.0 : unit(rng) * 250.0);
      // When the ring is estimated both ways
      const auto ours = estimate_radius(edges, cx, cy, lo, hi);
      const auto reference = estimate_radius_reference(edges, cx, cy, lo, hi);
      // Then they agree exactly
      ASSERT_EQ(ours.has_value(), reference.has_value())
          << cx << " " << cy << " " << lo << " " << hi;
      if (ours) {
        EXPECT_EQ(*ours, *reference);
        ++found;
      }
    }
  }
  EXPECT_GE(found, 100);
}

// angular_coverage_in_frame as it was: every sector's midpoint tested against the frame.
double coverage_in_frame_reference(const Circle& c, std::span<const cv::Point2d> points,
                                   const cv::Rect2d& frame, double min_inside,
                                   const OutlineStretch& stretch) {
  const double pi = std::numbers::pi;
  const int sectors = std::clamp(static_cast<int>(2.0 * pi * c.radius_px / 3.0), 8, 180);
  std::vector<unsigned char> inside(static_cast<std::size_t>(sectors), 0);
  int inside_count = 0;
  for (int s = 0; s < sectors; ++s) {
    const double a = (s + 0.5) * 2.0 * pi / sectors - pi;
    const cv::Point2d on =
        stretch.from_round({c.radius_px * std::cos(a), c.radius_px * std::sin(a)});
    const double x = c.x_px + on.x, y = c.y_px + on.y;
    if (x >= frame.x + 1.0 && y >= frame.y + 1.0 && x <= frame.x + frame.width - 2.0 &&
        y <= frame.y + frame.height - 2.0) {
      inside[static_cast<std::size_t>(s)] = 1;
      ++inside_count;
    }
  }
  if (inside_count == 0 || inside_count < min_inside * sectors) return 0.0;
  std::vector<unsigned char> hit(static_cast<std::size_t>(sectors), 0);
  for (const auto& p : points) {
    const double a = std::atan2(p.y - c.y_px, p.x - c.x_px) + pi;
    const int s = std::min(sectors - 1, static_cast<int>(a / (2.0 * pi) * sectors));
    hit[static_cast<std::size_t>(s)] = inside[static_cast<std::size_t>(s)];
  }
  return static_cast<double>(std::count(hit.begin(), hit.end(), 1)) / inside_count;
}

TEST(CoverageInFrame, GivenCirclesInsideAcrossAndNearTheBorderThenCoverageEqualsEverySectorTested) {
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const cv::Rect2d frame(-3.0, -2.0, 320.0, 240.0);
  int whole = 0, cut = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Given a circle anywhere around the frame (many just inside or just across its border),
    // a stretch (none or up to 1.6 along any axis) and points near its outline
    const Circle c{frame.x - 40.0 + unit(rng) * (frame.width + 80.0),
                   frame.y - 40.0 + unit(rng) * (frame.height + 80.0), 2.0 + unit(rng) * 60.0, 0.0};
    OutlineStretch stretch;
    if (trial % 2 == 1) {
      const double angle = unit(rng) * std::numbers::pi;
      stretch = OutlineStretch{{std::cos(angle), std::sin(angle)}, 1.0 + 0.6 * unit(rng)};
    }
    std::vector<cv::Point2d> points;
    for (int i = 0; i < 40; ++i) {
      const double a = unit(rng) * 2.0 * std::numbers::pi;
      points.emplace_back(c.x_px + c.radius_px * std::cos(a), c.y_px + c.radius_px * std::sin(a));
    }
    const double min_inside = trial % 3 == 0 ? 0.0 : 0.5;
    // When coverage is measured both ways
    const double ours = angular_coverage_in_frame(c, points, frame, min_inside, stretch);
    const double reference = coverage_in_frame_reference(c, points, frame, min_inside, stretch);
    // Then it is the same number
    ASSERT_EQ(ours, reference) << "trial " << trial;
    (reference > 0.0 && reference == angular_coverage(c, points) ? whole : cut) += 1;
  }
  EXPECT_GE(whole, 300);
  EXPECT_GE(cut, 300);
}

// Whether two doubles have the same bits (NaN payloads and signed zeros included).
bool same_bits(double a, double b) {
  return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b);
}

TEST(SmallSolve, GivenRandomNormalAndGeneralSystemsThenTheSolutionHasCvSolvesBits) {
  std::mt19937 rng(53);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int solved = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    // Given a 3 x 3 system: a normal matrix (sums of products, as the circle fit builds) or any
    // matrix, with entries over many magnitudes, some singular (a repeated row)
    const double scale = std::pow(10.0, 6.0 * unit(rng));
    cv::Matx33d a;
    if (trial % 2 == 0) {
      a = cv::Matx33d::zeros();
      for (int k = 0; k < 3 + trial % 40; ++k) {
        const cv::Vec3d row(scale * unit(rng), scale * unit(rng), 1.0);
        a += row * row.t();
      }
    } else {
      for (int i = 0; i < 9; ++i) a.val[i] = scale * unit(rng);
    }
    if (trial % 97 == 0)
      for (int j = 0; j < 3; ++j) a(2, j) = a(1, j);
    const cv::Vec3d b(scale * unit(rng), unit(rng), scale * scale * unit(rng));
    // When it is solved by solve_3x3 and by cv::solve
    const auto ours = solve_3x3(a, b);
    cv::Vec3d theirs;
    const bool ok = cv::solve(a, b, theirs, cv::DECOMP_CHOLESKY);
    // Then both fail, or both give the same bits
    ASSERT_EQ(ours.has_value(), ok) << "trial " << trial;
    if (ok) {
      ++solved;
      for (int i = 0; i < 3; ++i) ASSERT_TRUE(same_bits((*ours)[i], theirs[i])) << trial;
    }
    // And likewise the upper-left 2 x 2 block
    const cv::Matx22d a2(a(0, 0), a(0, 1), a(1, 0), a(1, 1));
    const auto ours2 = solve_2x2(a2, cv::Vec2d(b[0], b[1]));
    cv::Vec2d theirs2;
    ASSERT_EQ(ours2.has_value(),
              cv::solve(a2, cv::Vec2d(b[0], b[1]), theirs2, cv::DECOMP_CHOLESKY));
    for (int i = 0; ours2 && i < 2; ++i) ASSERT_TRUE(same_bits((*ours2)[i], theirs2[i])) << trial;
  }
  EXPECT_GE(solved, 19000);
  EXPECT_FALSE(solve_3x3(cv::Matx33d::zeros(), cv::Vec3d(1, 2, 3)).has_value());
}

// One Gauss-Newton round of fit_circle written plainly (the robust cut by nth_element, every sum
// of the 3 x 3 normal matrix point by point, cv::solve): the change of (cx, cy, r), or nullopt.
std::optional<cv::Vec3d> reference_round(const std::vector<cv::Point2d>& points,
                                         const cv::Point2d& mean, double cx, double cy, double r,
                                         double robust_floor_px, bool hold) {
  const int n = static_cast<int>(points.size());
  double cut = 0.0;
  if (robust_floor_px > 0.0) {
    std::vector<double> res;
    for (const auto& p : points)
      res.push_back(std::abs(std::sqrt((p.x - mean.x - cx) * (p.x - mean.x - cx) +
                                       (p.y - mean.y - cy) * (p.y - mean.y - cy)) -
                             r));
    std::nth_element(res.begin(), res.begin() + n / 2, res.end());
    cut = std::min(std::max(robust_floor_px, 4.685 * 1.4826 * res[n / 2]), 2.0 * robust_floor_px);
  }
  cv::Matx33d jtj = cv::Matx33d::zeros();
  cv::Vec3d jtr(0, 0, 0);
  for (const auto& p : points) {
    const double x = p.x - mean.x - cx, y = p.y - mean.y - cy;
    const double d = std::sqrt(x * x + y * y);
    if (d < 1e-9) continue;
    const cv::Vec3d j(-x / d, -y / d, -1.0);
    const double res = d - r;
    const double u = cut > 0.0 ? res / cut : 0.0;
    const double w = cut <= 0.0 ? 1.0 : u * u >= 1.0 ? 0.0 : (1.0 - u * u) * (1.0 - u * u);
    if (w <= 0.0) continue;
    for (int a = 0; a < 3; ++a) {
      jtr[a] += w * j[a] * res;
      for (int b = 0; b < 3; ++b) jtj(a, b) += w * j[a] * j[b];
    }
  }
  cv::Vec3d delta(0, 0, 0);
  if (hold) {
    cv::Vec2d d2;
    if (!cv::solve(cv::Matx22d(jtj(0, 0), jtj(0, 1), jtj(1, 0), jtj(1, 1)),
                   cv::Vec2d(-jtr[0], -jtr[1]), d2, cv::DECOMP_CHOLESKY))
      return std::nullopt;
    return cv::Vec3d(d2[0], d2[1], 0.0);
  }
  if (!cv::solve(jtj, -jtr, delta, cv::DECOMP_CHOLESKY)) return std::nullopt;
  return delta;
}

// fit_circle written plainly (the Kasa start's 3 x 3 sums point by point, cv::solve, then
// reference_round): the reference its fast paths must equal bit for bit.
std::optional<Circle> fit_circle_reference(const std::vector<cv::Point2d>& points,
                                           double robust_floor_px, double fixed_radius_px) {
  const int n = static_cast<int>(points.size());
  if (n < 3) return std::nullopt;
  cv::Point2d mean(0, 0);
  for (const auto& p : points) mean += p;
  mean *= 1.0 / n;
  cv::Matx33d ata = cv::Matx33d::zeros();
  cv::Vec3d atb(0, 0, 0);
  for (const auto& p : points) {
    const double x = p.x - mean.x, y = p.y - mean.y;
    const cv::Vec3d row(x, y, 1.0);
    const double rhs = -(x * x + y * y);
    for (int i = 0; i < 3; ++i) {
      atb[i] += row[i] * rhs;
      for (int j = 0; j < 3; ++j) ata(i, j) += row[i] * row[j];
    }
  }
  cv::Vec3d sol;
  if (!cv::solve(ata, atb, sol, cv::DECOMP_CHOLESKY)) return std::nullopt;
  double cx = -sol[0] / 2.0, cy = -sol[1] / 2.0;
  const double r2 = cx * cx + cy * cy - sol[2];
  if (!(r2 > 0.0)) return std::nullopt;
  const bool hold = fixed_radius_px > 0.0;
  double r = hold ? fixed_radius_px : std::sqrt(r2);
  for (int it = 0; it < (robust_floor_px > 0.0 ? 8 : 5); ++it) {
    const auto delta = reference_round(points, mean, cx, cy, r, robust_floor_px, hold);
    if (!delta) break;
    cx += (*delta)[0];
    cy += (*delta)[1];
    r += (*delta)[2];
    if (std::abs((*delta)[0]) + std::abs((*delta)[1]) + std::abs((*delta)[2]) < 1e-4) break;
  }
  if (!(r > 0.0) || !std::isfinite(cx) || !std::isfinite(cy)) return std::nullopt;
  return Circle{cx + mean.x, cy + mean.y, r, 0.0};
}

TEST(FitCircle, GivenNoisyArcsWithOutliersOfEveryCountThenTheFitHasThePlainReferencesBits) {
  std::mt19937 rng(61);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  int fitted = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Given points on an arc of a circle (sub-pixel noise, from almost none, so that the robust
    // cut is the floor, to half a pixel, twice the floor; some texture points off it), of any
    // count (every remainder of four), some exactly on the centre
    const double sigma = 0.01 + 0.5 * unit(rng);
    const cv::Point2d centre(500.0 * unit(rng), 400.0 * unit(rng));
    const double radius = 3.0 + 120.0 * unit(rng);
    const double start = 2.0 * std::numbers::pi * unit(rng);
    const double span = (0.3 + 1.7 * unit(rng)) * std::numbers::pi;
    std::vector<cv::Point2d> points;
    const int count = 3 + trial % 300;
    for (int i = 0; i < count; ++i) {
      const double a = start + span * unit(rng);
      const double rr =
          unit(rng) < 0.15 ? radius * (0.6 + 0.5 * unit(rng)) : radius + sigma * noise(rng);
      points.emplace_back(centre.x + rr * std::cos(a), centre.y + rr * std::sin(a));
    }
    if (trial % 50 == 0) points.push_back(centre);
    const double floor_px = trial % 3 == 0 ? 0.0 : 0.6;
    const double fixed = trial % 5 == 0 ? radius * (0.9 + 0.2 * unit(rng)) : 0.0;
    // When fitted by fit_circle and by the reference
    const auto ours = fit_circle(points, floor_px, fixed);
    const auto reference = fit_circle_reference(points, floor_px, fixed);
    // Then both fail or both give the same bits
    ASSERT_EQ(ours.has_value(), reference.has_value()) << "trial " << trial;
    if (!ours) continue;
    ++fitted;
    ASSERT_TRUE(same_bits(ours->x_px, reference->x_px)) << "trial " << trial;
    ASSERT_TRUE(same_bits(ours->y_px, reference->y_px)) << "trial " << trial;
    ASSERT_TRUE(same_bits(ours->radius_px, reference->radius_px)) << "trial " << trial;
  }
  EXPECT_GE(fitted, 2900);
}

// The sub-pixel position of edge pixel (x, y) written plainly: the parabola through |dx| + |dy|
// at the pixel and its neighbours along the gradient's nearest of eight directions.
cv::Point2d reference_subpixel(const EdgeMap& edges, int x, int y) {
  if (x < 1 || y < 1 || x >= edges.dx.cols - 1 || y >= edges.dx.rows - 1)
    return {double(x), double(y)};
  const auto l1 = [&](int px, int py) {
    return std::abs(edges.dx.at<short>(py, px)) + std::abs(edges.dy.at<short>(py, px));
  };
  const int gx = edges.dx.at<short>(y, x), gy = edges.dy.at<short>(y, x);
  const int agx = std::abs(gx), agy = std::abs(gy);
  int sx = 1, sy = 0;
  if (agy * 128 > agx * 53) {
    if (agx * 128 <= agy * 53)
      sx = 0, sy = 1;
    else
      sy = (gx > 0) == (gy > 0) ? 1 : -1;
  }
  const double m0 = l1(x, y), mm = l1(x - sx, y - sy), mp = l1(x + sx, y + sy);
  const double denom = mm - 2.0 * m0 + mp;
  if (denom >= 0.0) return {double(x), double(y)};
  const double t = std::clamp(0.5 * (mm - mp) / denom, -0.5, 0.5);
  return {x + t * sx, y + t * sy};
}

// gather_outline_points written plainly: every edge pixel around the band in raster order through
// the band and gradient tests, then placed (the same arithmetic, expression by expression).
std::vector<cv::Point2d> gather_reference(const EdgeMap& edges, const Circle& round,
                                          const OutlineStretch& stretch, double band_px,
                                          double min_cos) {
  const double cx = round.x_px, cy = round.y_px;
  const double outer = round.radius_px + band_px;
  const double inner = std::max(0.0, round.radius_px - band_px);
  const double ax = stretch.axis.x, ay = stretch.axis.y;
  const double to_round = 1.0 / stretch.ratio - 1.0, from_round = stretch.ratio - 1.0;
  // Every pixel of the box around the band (a pixel beyond it fails the band test).
  const double reach = stretch.ratio * outer + 2.0;
  const int x0 = std::max(0, static_cast<int>(cx - reach));
  const int x1 = std::min(edges.bits.width() - 1, static_cast<int>(cx + reach));
  const int y0 = std::max(0, static_cast<int>(cy - reach));
  const int y1 = std::min(edges.bits.height() - 1, static_cast<int>(cy + reach));
  std::vector<cv::Point2d> out;
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x) {
      if (!edges.bits.test(x, y)) continue;
      const int gx = edges.dx.at<short>(y, x), gy = edges.dy.at<short>(y, x);
      double rx = x - cx, ry = y - cy, g_x = gx, g_y = gy;
      if (!stretch.identity()) {
        const double k = to_round * (rx * ax + ry * ay);
        rx = rx + ax * k;
        ry = ry + ay * k;
        const double kg = from_round * (g_x * ax + g_y * ay);
        g_x = g_x + ax * kg;
        g_y = g_y + ay * kg;
      }
      const double d2 = rx * rx + ry * ry;
      const double g_dot_r = g_x * rx + g_y * ry, g2 = g_x * g_x + g_y * g_y;
      if (d2 > outer * outer || d2 < inner * inner ||
          g_dot_r * g_dot_r < min_cos * min_cos * g2 * d2)
        continue;
      cv::Point2d p = reference_subpixel(edges, x, y);
      if (!stretch.identity()) {
        const double sx = p.x - cx, sy = p.y - cy;
        const double k = to_round * (sx * ax + sy * ay);
        p = {cx + (sx + ax * k), cy + (sy + ay * k)};
      }
      const double sd = std::sqrt((p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy));
      if (sd > outer || sd < inner) continue;
      out.push_back(p);
    }
  return out;
}

TEST(GatherOutlinePoints, GivenRealEdgeMapsAndBandsAnywhereThenPointsEqualAScanOfEveryEdgePixel) {
  // Given the real images' colour edge maps
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u);
  std::mt19937 rng(67);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t gathered = 0;
  for (const auto& image : images) {
    EdgeMap edges;
    compute_edge_map(image, EdgeParams{}, edges);
    for (int trial = 0; trial < 60; ++trial) {
      // And a band anywhere (across the border too), of any width, round or stretched
      const Circle round{-20.0 + (image.cols + 40.0) * unit(rng),
                         -20.0 + (image.rows + 40.0) * unit(rng), 2.0 + 150.0 * unit(rng), 0.0};
      OutlineStretch stretch;
      if (trial % 2 == 1) {
        const double angle = unit(rng) * std::numbers::pi;
        stretch = OutlineStretch{{std::cos(angle), std::sin(angle)}, 1.0 + 0.3 * unit(rng)};
      }
      const double band = 0.5 + 4.0 * unit(rng);
      const double min_cos = trial % 3 == 0 ? 0.0 : 0.85;
      // When its points are gathered and found by the plain scan
      std::vector<cv::Point2d> ours;
      gather_outline_points(edges, round, stretch, band, min_cos, ours);
      const auto reference = gather_reference(edges, round, stretch, band, min_cos);
      // Then they are the same points in the same order, bit for bit
      ASSERT_EQ(ours.size(), reference.size()) << "trial " << trial;
      for (std::size_t i = 0; i < ours.size(); ++i)
        ASSERT_TRUE(same_bits(ours[i].x, reference[i].x) && same_bits(ours[i].y, reference[i].y))
            << "trial " << trial << " point " << i;
      gathered += ours.size();
    }
  }
  EXPECT_GE(gathered, 10000u);
}

TEST(RefineCircle, GivenSeedsOnRealEdgeMapsThenItsScoreEqualsAFreshScoreOfTheCircleItReturns) {
  // Given the real images' colour edge maps, and refinement settings with and without the
  // clutter rings, the robust wide first band and a camera (stretched outlines)
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u);
  std::mt19937 rng(71);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  int refined = 0;
  for (const auto& image : images) {
    EdgeMap edges;
    compute_edge_map(image, EdgeParams{}, edges);
    for (int trial = 0; trial < 40; ++trial) {
      RefineParams params;
      if (trial % 2 == 1) {
        params.clutter_ring_per_radius = 0.1;
        params.clutter_min_radius_px = 10.0;
      }
      if (trial % 3 == 1) {
        params.first_band_px = 4.0;
        params.robust_fit_floor_px = 0.6;
      }
      if (trial % 4 >= 2)
        params.camera =
            stereo::PinholeCamera{0.6 * image.cols, {0.5 * image.cols, 0.5 * image.rows}};
      const Circle seed{image.cols * unit(rng), image.rows * unit(rng), 6.0 + 80.0 * unit(rng),
                        0.0};
      // When a seed is refined (its later bands taking their pixels from its first band's scan)
      const auto c = refine_circle(edges, seed, params);
      if (!c) continue;
      ++refined;
      // Then its score is that of the circle scored on its own (a scan of its own band)
      ASSERT_TRUE(same_bits(c->score, score_circle(edges, *c, params))) << "trial " << trial;
    }
  }
  EXPECT_GE(refined, 100);
}

// The comparison chain orientation_bin was written as first (branches), the reference.
int orientation_bin_chain(int gx, int gy) {
  if (gy < 0 || (gy == 0 && gx < 0)) {
    gx = -gx;
    gy = -gy;
  }
  const float ax = static_cast<float>(gx < 0 ? -gx : gx), fy = static_cast<float>(gy);
  const int b = fy < 0.41421356f * ax ? 0 : fy < ax ? 1 : fy < 2.41421356f * ax ? 2 : 3;
  return gx >= 0 ? b : 7 - b;
}

TEST(OrientationBin, GivenEveryGradientASobelGivesThenTheBinIsTheComparisonChains) {
  // Given every (gx, gy) a colour or grey 3x3 Sobel of 8-bit pixels can give (|g| <= 1020)
  for (int gx = -1024; gx <= 1024; ++gx)
    for (int gy = -1024; gy <= 1024; ++gy)
      // When binned without branches, then the bin is the chain's
      ASSERT_EQ(orientation_bin(gx, gy), orientation_bin_chain(gx, gy)) << gx << ", " << gy;
}

TEST(NearOrientationPlanes, GivenRealEdgeMapsThenEachPlaneHoldsThePointsWithinTheSlackOfItsBin) {
  // Given the real images' colour edge maps
  const auto images = real_colours();
  ASSERT_GE(images.size(), 10u);
  for (const auto& image : images) {
    EdgeMap edges;
    compute_edge_map(image, EdgeParams{}, edges);
    // When the planes are built word by word
    std::array<BitImage, kOrientationBins> planes;
    near_orientation_planes(edges, planes);
    // Then they equal the planes set point by point
    std::array<BitImage, kOrientationBins> reference;
    for (BitImage& plane : reference) plane.reset(edges.bits.width(), edges.bits.height());
    for (int y = 0; y < edges.edges.rows; ++y)
      for (int x = 0; x < edges.edges.cols; ++x) {
        if (!edges.bits.test(x, y)) continue;
        const int bin = orientation_bin(edges.dx.at<short>(y, x), edges.dy.at<short>(y, x));
        for (int d = -kOrientationSlackBins; d <= kOrientationSlackBins; ++d)
          reference[static_cast<std::size_t>((bin + d + kOrientationBins) % kOrientationBins)].set(
              x, y);
      }
    for (int b = 0; b < kOrientationBins; ++b)
      for (int y = 0; y < edges.bits.height(); ++y)
        for (int wi = 0; wi * 64 < edges.bits.width(); ++wi)
          ASSERT_EQ(planes[static_cast<std::size_t>(b)].row(y)[wi],
                    reference[static_cast<std::size_t>(b)].row(y)[wi])
              << "bin " << b << " row " << y;
  }
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
