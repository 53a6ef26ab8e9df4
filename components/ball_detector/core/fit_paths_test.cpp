// The circle fit's arithmetic against plain references: solve_3x3 / solve_2x2 vs cv::solve and
// fit_circle vs its plain arithmetic, bit for bit. Part of the detector's fast-path checks
// (detector_paths_test.cpp).
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/fast_math.hpp"
#include "ball_detector/core/same_circles_test_support.hpp"

namespace stereoball::ball_detector {
namespace {

using test::same_bits;

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

}  // namespace
}  // namespace stereoball::ball_detector
