#include "ball_detector/pipeline/outline_refit.hpp"

#include "stereo/core/sphere_outline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace stereoball::ball_detector {
namespace {

bool same_circle(const Circle& a, const Circle& b) {
  return a.x_px == b.x_px && a.y_px == b.y_px && a.radius_px == b.radius_px;
}

}  // namespace

std::optional<Circle> unmoved_partner_outline(const PairingContext& ctx, const Circle& seen,
                                              bool seen_right) {
  const stereo::Triangulator& tri = ctx.triangulator;
  const stereo::PinholeCamera left{tri.focal_px(), tri.principal_left_px()};
  const stereo::PinholeCamera right{tri.focal_px(), tri.principal_right_px()};
  const auto view = stereo::sphere_from_outline(seen_right ? right : left, {seen.x_px, seen.y_px},
                                                seen.radius_px);
  if (!view) return std::nullopt;
  const double r_m = 0.5 * ctx.size.ball_diameter_m;
  const double z_m = view->depth_m(r_m);
  if (!(z_m > r_m)) return std::nullopt;
  const double t = view->tan_off_axis;
  const cv::Vec3d centre(t * view->major_axis.x * z_m, t * view->major_axis.y * z_m, z_m);
  // The right camera sits baseline_m to the left camera's right (x), rows shared.
  const cv::Vec3d shift(tri.baseline_m(), 0.0, 0.0);
  const auto o = seen_right ? stereo::sphere_outline(left, centre + shift, r_m)
                            : stereo::sphere_outline(right, centre - shift, r_m);
  if (!o) return std::nullopt;
  return Circle{o->centre_px.x, o->centre_px.y, o->mean_radius_px(), 0.0};
}

MovedRadii moved_radii(const PairingContext& ctx, const StereoPair& pair) {
  MovedRadii m;
  const stereo::Triangulator& tri = ctx.triangulator;
  const stereo::PinholeCamera left{tri.focal_px(), tri.principal_left_px()};
  const stereo::PinholeCamera right{tri.focal_px(), tri.principal_right_px()};
  const double r_m = 0.5 * ctx.size.ball_diameter_m;
  const cv::Vec3d shift(tri.baseline_m(), 0.0, 0.0);
  const auto seen_left = stereo::sphere_outline(left, pair.position_m, r_m);
  const auto seen_right = stereo::sphere_outline(right, pair.position_m - shift, r_m);
  double depth_m = pair.position_m[2];
  if (pair.depth_from_size_m > 0.0) depth_m = std::min(depth_m, pair.depth_from_size_m);
  if (!seen_left || !seen_right || !(depth_m > 0.0)) return m;
  const double left_as_right =
      pair.left.radius_px * seen_right->mean_radius_px() / seen_left->mean_radius_px();
  const double moved_m = std::max(0.0, ctx.motion_radii) * r_m;
  m.difference_px = std::abs(left_as_right - pair.right.radius_px);
  m.allowed_px = std::max(left_as_right, pair.right.radius_px) * moved_m / depth_m +
                 ctx.epipolar.params().max_row_diff_px;
  m.agree = m.difference_px <= m.allowed_px;
  return m;
}

RefitVerdict judge_refit(const PairingContext& ctx, const Circle& found_left,
                         const Circle& found_right, const Circle& left, const Circle& right) {
  RefitVerdict v;
  v.changed = !same_circle(found_left, left) || !same_circle(found_right, right);
  if (!v.changed) return v;
  auto pair = evaluate_pair(ctx, left, right);
  char text[200];
  if (pair && pair->size_consistent && pair->on_floor) {
    v.pair = pair;
    std::snprintf(text, sizeof text,
                  "outlines refitted to the arcs that agree (left r %.1f, right r %.1f px)",
                  left.radius_px, right.radius_px);
  } else {
    std::snprintf(text, sizeof text,
                  "refitted to the arcs that agree, the outlines (left %.0f,%.0f r %.1f; right "
                  "%.0f,%.0f r %.1f px) are not one ball's: %s",
                  left.x_px, left.y_px, left.radius_px, right.x_px, right.y_px, right.radius_px,
                  !pair
                      ? "rows or disparity do not pair"
                      : (!pair->size_consistent ? "size and disparity disagree" : "off the floor"));
  }
  v.note = text;
  return v;
}

}  // namespace stereoball::ball_detector
