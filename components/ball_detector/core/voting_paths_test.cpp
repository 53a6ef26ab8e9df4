// The voting primitives against plain references: find_peaks vs a brute-force scan, plot_ray
// vs a bounds test per cell, orientation_bin vs its comparison chain and the orientation planes
// vs points set one by one. Part of the detector's fast-path checks (detector_paths_test.cpp).
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/p2p_rules.hpp"
#include "ball_detector/core/voting.hpp"

namespace stereoball::ball_detector {
namespace {

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

}  // namespace
}  // namespace stereoball::ball_detector
