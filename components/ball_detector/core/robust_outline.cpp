// robust_outline and outline_coverage: a ball's outline partly hidden (fingers) or crossed (seams)
// found by sampling circles through three edge points near a rough circle, each judged by the
// coverage of the points that support it (band, radial gradient, ball colour inside only).
// Apart from refine_circle (circle_refine.cpp): it searches around a circle instead of fitting
// one band.
#include "ball_detector/core/circle_fit.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

namespace stereoball::ball_detector {
namespace {

// An edge point of the annulus around a rough circle, with its unit gradient.
struct OutlinePoint {
  cv::Point2d p;
  cv::Point2d g;
};

// The circle through three points; nullopt when they are (nearly) collinear.
std::optional<Circle> circle_through(const cv::Point2d& a, const cv::Point2d& b,
                                     const cv::Point2d& c) {
  const double d = 2.0 * (a.x * (b.y - c.y) + b.x * (c.y - a.y) + c.x * (a.y - b.y));
  if (std::abs(d) < 1e-6) return std::nullopt;
  const double a2 = a.dot(a), b2 = b.dot(b), c2 = c.dot(c);
  const double x = (a2 * (b.y - c.y) + b2 * (c.y - a.y) + c2 * (a.y - b.y)) / d;
  const double y = (a2 * (c.x - b.x) + b2 * (a.x - c.x) + c2 * (b.x - a.x)) / d;
  return Circle{x, y, std::hypot(a.x - x, a.y - y), 0.0};
}

// Whether q's gradient is radial to circle c within min_cos.
bool radial(const Circle& c, const OutlinePoint& q, double min_cos) {
  const cv::Point2d d(q.p.x - c.x_px, q.p.y - c.y_px);
  const double n = std::hypot(d.x, d.y);
  return n > 0.0 && std::abs(d.dot(q.g)) >= min_cos * n;
}

double band_of(const Circle& c, const OutlineSearchParams& params) {
  return std::max(params.band_px, params.band_per_radius * c.radius_px);
}

// The ball's own colour: per-channel medians over rings at 0.2-0.6 of rough's radius (the
// inside, clear of an outline that is off by a fifth of the radius).
struct SideTest {
  const cv::Mat* image = nullptr;  // CV_8UC3 or CV_8UC1, the edge map's
  cv::Vec3d ball{0, 0, 0};
  double min_contrast = 0.0;

  cv::Vec3d at(const cv::Point2d& p) const {
    const int x = std::clamp(static_cast<int>(std::lround(p.x)), 0, image->cols - 1);
    const int y = std::clamp(static_cast<int>(std::lround(p.y)), 0, image->rows - 1);
    if (image->channels() == 3) {
      const cv::Vec3b v = image->at<cv::Vec3b>(y, x);
      return {double(v[0]), double(v[1]), double(v[2])};
    }
    const double g = image->at<std::uint8_t>(y, x);
    return {g, g, g};
  }
  // Whether the point at p (radial unit u, away from the centre) has the ball's colour inside
  // and something else just outside: an outline, not a seam (ball colour on both sides) or a
  // shading step.
  bool outline_at(const cv::Point2d& p, const cv::Point2d& u, double reach) const {
    if (!image) return true;
    const double in = cv::norm(at(p - reach * u) - ball);
    const double out = cv::norm(at(p + reach * u) - ball);
    return out - in >= min_contrast;
  }
};

SideTest side_test(const EdgeMap& edges, const Circle& rough, double min_contrast) {
  SideTest t;
  const cv::Mat& image = !edges.colour.empty() ? edges.colour : edges.grey;
  if (!(min_contrast > 0.0) || image.empty()) return t;
  t.image = &image;
  t.min_contrast = min_contrast;
  std::array<std::vector<double>, 3> ch;
  for (const double f : {0.2, 0.4, 0.6})
    for (int a = 0; a < 24; ++a) {
      const double ang = 2.0 * std::numbers::pi * (a + 0.5 * f) / 24;
      const cv::Vec3d v = t.at({rough.x_px + f * rough.radius_px * std::cos(ang),
                                rough.y_px + f * rough.radius_px * std::sin(ang)});
      for (int k = 0; k < 3; ++k) ch[k].push_back(v[k]);
    }
  for (int k = 0; k < 3; ++k) {
    auto mid = ch[k].begin() + static_cast<std::ptrdiff_t>(ch[k].size() / 2);
    std::nth_element(ch[k].begin(), mid, ch[k].end());
    t.ball[k] = *mid;
  }
  return t;
}

// The points supporting c (within its band, radial gradient, an outline by their sides).
void supporters(const Circle& c, std::span<const OutlinePoint> pts,
                const OutlineSearchParams& params, const SideTest& sides,
                std::vector<cv::Point2d>& out) {
  out.clear();
  const double band = band_of(c, params);
  const double reach = std::max(2.0, params.side_reach_per_radius * c.radius_px);
  for (const OutlinePoint& q : pts) {
    const cv::Point2d d(q.p.x - c.x_px, q.p.y - c.y_px);
    const double dist = std::hypot(d.x, d.y);
    if (std::abs(dist - c.radius_px) <= band && radial(c, q, params.min_radial_cos) &&
        sides.outline_at(q.p, d / dist, reach))
      out.push_back(q.p);
  }
}

// Edge points of edges within reach of rough's outline (the slacks), with unit gradients.
void annulus_points(const EdgeMap& edges, const Circle& rough, const OutlineSearchParams& params,
                    std::vector<OutlinePoint>& out) {
  out.clear();
  const double r = rough.radius_px;
  const double reach = params.centre_slack * r + params.band_px + params.band_per_radius * r;
  const double lo = std::max(0.0, (1.0 - params.radius_slack) * r - reach);
  const double hi = (1.0 + params.radius_slack) * r + reach;
  const EdgePoints& e = edges.points;
  for (std::size_t i = 0; i < e.x.size(); ++i) {
    const double dx = e.x[i] - rough.x_px, dy = e.y[i] - rough.y_px;
    const double d2 = dx * dx + dy * dy;
    if (d2 < lo * lo || d2 > hi * hi) continue;
    const double gn = std::hypot(static_cast<double>(e.gx[i]), static_cast<double>(e.gy[i]));
    if (gn <= 0.0) continue;
    out.push_back(
        {{static_cast<double>(e.x[i]), static_cast<double>(e.y[i])}, {e.gx[i] / gn, e.gy[i] / gn}});
  }
}

}  // namespace

double outline_coverage(const EdgeMap& edges, const Circle& c, const OutlineSearchParams& params) {
  std::vector<OutlinePoint> pts;
  OutlineSearchParams exact = params;
  exact.radius_slack = exact.centre_slack = 0.0;
  annulus_points(edges, c, exact, pts);
  std::vector<cv::Point2d> support;
  supporters(c, pts, params, side_test(edges, c, params.min_side_contrast), support);
  return angular_coverage_in_frame(c, support, edges.frame_px);
}

std::optional<Circle> robust_outline(const EdgeMap& edges, const Circle& rough,
                                     const OutlineSearchParams& params) {
  if (!(rough.radius_px > 0.0) || !std::isfinite(rough.x_px) || !std::isfinite(rough.y_px))
    return std::nullopt;
  std::vector<OutlinePoint> pts;
  annulus_points(edges, rough, params, pts);
  std::vector<cv::Point2d> support;
  const SideTest sides = side_test(edges, rough, params.min_side_contrast);
  const auto coverage = [&](const Circle& c) {
    supporters(c, pts, params, sides, support);
    return angular_coverage_in_frame(c, support, edges.frame_px);
  };
  Circle kept = rough;
  kept.score = coverage(rough);
  if (pts.size() < 3) return kept;
  const double r = rough.radius_px;
  const double r_lo = (1.0 - params.radius_slack) * r, r_hi = (1.0 + params.radius_slack) * r;
  const double max_shift = params.centre_slack * r;
  // Three points of one outline lie well apart on it: closer ones give an ill-posed circle.
  const double min_apart = 0.5 * r_lo;
  cv::RNG rng(0x5eed);
  const int n = static_cast<int>(pts.size());
  Circle best = kept;
  std::size_t best_support = support.size();
  for (int h = 0; h < params.hypotheses; ++h) {
    const OutlinePoint& a = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    const OutlinePoint& b = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    const OutlinePoint& c = pts[static_cast<std::size_t>(rng.uniform(0, n))];
    if (cv::norm(a.p - b.p) < min_apart || cv::norm(b.p - c.p) < min_apart ||
        cv::norm(a.p - c.p) < min_apart)
      continue;
    const auto circle = circle_through(a.p, b.p, c.p);
    if (!circle || circle->radius_px < r_lo || circle->radius_px > r_hi ||
        std::hypot(circle->x_px - rough.x_px, circle->y_px - rough.y_px) > max_shift)
      continue;
    if (!radial(*circle, a, params.min_radial_cos) || !radial(*circle, b, params.min_radial_cos) ||
        !radial(*circle, c, params.min_radial_cos))
      continue;
    const double cov = coverage(*circle);
    if (cov > best.score || (cov == best.score && support.size() > best_support)) {
      best = *circle;
      best.score = cov;
      best_support = support.size();
    }
  }
  if (best.score < kept.score + params.min_gain) return kept;
  // The supporters' least-squares circle (Tukey weights), twice: it sits on the outline, not
  // on the three sampled points.
  for (int round = 0; round < 2; ++round) {
    supporters(best, pts, params, sides, support);
    const auto fit = fit_circle(support, 0.6);
    if (!fit || fit->radius_px < r_lo || fit->radius_px > r_hi ||
        std::hypot(fit->x_px - rough.x_px, fit->y_px - rough.y_px) > max_shift)
      break;
    const double cov = coverage(*fit);
    if (cov < best.score) break;
    best = *fit;
    best.score = cov;
  }
  return best;
}

}  // namespace stereoball::ball_detector
