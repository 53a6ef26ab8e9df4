// The outline band's paths against plain references: estimate_radius vs a scan of every edge
// pixel, angular_coverage_in_frame vs every sector tested, gather_outline_points vs its plain
// arithmetic and refine_circle's reused scan vs a fresh one. Part of the detector's fast-path
// checks (detector_paths_test.cpp).
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/fast_paths_test_support.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"

namespace stereoball::ball_detector {
namespace {

using test::same_bits;

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

}  // namespace
}  // namespace stereoball::ball_detector
