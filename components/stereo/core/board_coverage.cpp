#include "stereo/core/board_coverage.hpp"

#include <algorithm>
#include <cmath>

namespace stereoball::stereo {
namespace {

double clamp01(double v) {
  return std::clamp(v, 0.0, 1.0);
}

// Angle at b between the rays to a and c, radians.
double angle_at(const cv::Point2d& a, const cv::Point2d& b, const cv::Point2d& c) {
  const cv::Point2d u = a - b, v = c - b;
  const double n = std::hypot(u.x, u.y) * std::hypot(v.x, v.y);
  if (n <= 0.0) return 0.0;
  return std::acos(std::clamp(u.dot(v) / n, -1.0, 1.0));
}

}  // namespace

std::optional<BoardViewParams> board_view_params(const std::vector<cv::Point2f>& corners_px,
                                                 cv::Size inner_corners, cv::Size image_size) {
  const int cols = inner_corners.width, rows = inner_corners.height;
  if (cols < 2 || rows < 2 || static_cast<int>(corners_px.size()) != cols * rows ||
      image_size.width <= 0 || image_size.height <= 0) {
    return std::nullopt;
  }
  const cv::Point2d tl = corners_px[0], tr = corners_px[cols - 1];
  const cv::Point2d br = corners_px[corners_px.size() - 1];
  const cv::Point2d bl = corners_px[corners_px.size() - static_cast<std::size_t>(cols)];
  // Shoelace area of the quad of the four outer inner corners.
  const cv::Point2d q[4] = {tl, tr, br, bl};
  double twice = 0.0;
  for (int i = 0; i < 4; ++i) twice += q[i].x * q[(i + 1) % 4].y - q[(i + 1) % 4].x * q[i].y;
  const double area = std::abs(twice) / 2.0;
  const double border = std::sqrt(area);
  double mx = 0.0, my = 0.0;
  for (const auto& p : corners_px) {
    mx += p.x;
    my += p.y;
  }
  mx /= static_cast<double>(corners_px.size());
  my /= static_cast<double>(corners_px.size());
  const double w = image_size.width, h = image_size.height;
  BoardViewParams v;
  v.x = w > border ? clamp01((mx - border / 2.0) / (w - border)) : 0.5;
  v.y = h > border ? clamp01((my - border / 2.0) / (h - border)) : 0.5;
  v.size = std::sqrt(area / (w * h));
  v.skew = std::min(1.0, 2.0 * std::abs(CV_PI / 2.0 - angle_at(tl, tr, br)));
  return v;
}

void BoardCoverage::add(const BoardViewParams& view) {
  const std::array<double, 4> p{view.x, view.y, view.size, view.skew};
  for (std::size_t i = 0; i < p.size(); ++i) {
    lo_[i] = views_ == 0 ? p[i] : std::min(lo_[i], p[i]);
    hi_[i] = views_ == 0 ? p[i] : std::max(hi_[i], p[i]);
  }
  ++views_;
}

std::array<double, 4> BoardCoverage::progress() const {
  std::array<double, 4> out{};
  if (views_ == 0) return out;
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::min(1.0, (hi_[i] - lo_[i]) / kGoal[i]);
  return out;
}

bool BoardCoverage::complete() const {
  const auto p = progress();
  return std::all_of(p.begin(), p.end(), [](double v) { return v >= 1.0; });
}

}  // namespace stereoball::stereo
