#include "ball_detector/pipeline/pairing.hpp"

#include "stereo/core/sphere_outline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace stereoball::ball_detector {
namespace {

std::string format(const char* fmt, double a, double b = 0.0, double c = 0.0, double d = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, a, b, c, d);
  return buf;
}

std::string no_candidate_reason(bool left_empty, bool right_empty) {
  if (left_empty && right_empty) return "no circle in either eye";
  return left_empty ? "no circle in the left eye" : "no circle in the right eye";
}

stereo::PinholeCamera left_camera(const stereo::Triangulator& tri) {
  return {tri.focal_px(), tri.principal_left_px()};
}

stereo::PinholeCamera right_camera(const stereo::Triangulator& tri) {
  return {tri.focal_px(), tri.principal_right_px()};
}

// Mean outline radius (what the detector's circle fit measures) of a ball of radius_m centred
// at centre_m in camera's frame; 0 if it has no outline.
double outline_radius_px(const stereo::PinholeCamera& camera, const cv::Vec3d& centre_m,
                         double radius_m) {
  const auto o = stereo::sphere_outline(camera, centre_m, radius_m);
  return o ? o->mean_radius_px() : 0.0;
}

// Depth of the ball behind an outline, metres, or nullopt.
std::optional<double> outline_depth_m(const stereo::PinholeCamera& camera, const Circle& c,
                                      double radius_m) {
  const auto view = stereo::sphere_from_outline(camera, {c.x_px, c.y_px}, c.radius_px);
  if (!view) return std::nullopt;
  return view->depth_m(radius_m);
}

// Between two frames the prediction errs far less than the gate allows (the gate is for
// choosing among pairs; a miss only costs a whole-frame search): a third of it, in depth and
// sideways.
double prior_slack_m(const PositionPrior& prior) {
  return prior.gate_m / 3.0;
}

// The left outline of the ball expected at prior moved by depth_shift_m along its line of
// sight (negative = nearer); nullopt if that depth is not beyond the ball's own radius.
std::optional<stereo::SphereOutline> prior_outline(const PairingContext& ctx,
                                                   const PositionPrior& prior,
                                                   double depth_shift_m) {
  const cv::Vec3d& p = prior.position_m;
  const double r_m = 0.5 * ctx.size.ball_diameter_m;
  const double z = p[2] + depth_shift_m;
  if (!(p[2] > 0.0) || !(z > r_m)) return std::nullopt;
  return stereo::sphere_outline(left_camera(ctx.triangulator), p * (z / p[2]), r_m);
}

// The prior's left outline at the nearest depth the slack allows, where the disc and the slack
// look largest, and how far the slack can move it sideways there, pixels.
struct NearOutline {
  stereo::SphereOutline outline;
  double slack_px = 0.0;
};

std::optional<NearOutline> prior_near_outline(const PairingContext& ctx,
                                              const PositionPrior& prior) {
  const double slack_m = prior_slack_m(prior);
  const auto outline = prior_outline(ctx, prior, -slack_m);
  if (!outline) return std::nullopt;
  const double near_z = prior.position_m[2] - slack_m;
  return NearOutline{*outline, ctx.triangulator.focal_px() * slack_m / near_z};
}

// How far outside image a point within slack_px of p can be, rounded up; 0 if nowhere.
double outside_by_px(const cv::Point2d& p, double slack_px, cv::Size image) {
  const double out = std::max({-p.x, p.x - (image.width - 1), -p.y, p.y - (image.height - 1)});
  return std::max(0.0, out + slack_px);
}

int margin_cap_px(double out_px, double cap_px) {
  return static_cast<int>(std::ceil(std::min(out_px, std::max(0.0, cap_px))));
}

// The disparities of a right-eye partner of a ball-sized sphere at depth_m: the size check
// accepts radii within the tolerance of the expected one, i.e. depths (and so disparities)
// within about that fraction.
struct DisparityRange {
  double lo = 0.0, hi = 0.0;
};

DisparityRange disparity_range(const PairingContext& ctx, double depth_m) {
  const double d = ctx.triangulator.focal_px() * ctx.triangulator.baseline_m() / depth_m;
  const double tol = ctx.size.max_relative_error;
  return {d * std::max(0.0, 1.0 - tol), d * (1.0 + tol)};
}

// The columns of those partners' centres.
struct PartnerColumns {
  double x_near = 0.0;  ///< nearest ball, leftmost centre, right rectified px
  double x_far = 0.0;
};

std::optional<PartnerColumns> partner_columns(const PairingContext& ctx, const Circle& left) {
  const stereo::Triangulator& tri = ctx.triangulator;
  const auto depth = outline_depth_m(left_camera(tri), left, 0.5 * ctx.size.ball_diameter_m);
  if (!depth) return std::nullopt;
  const DisparityRange range = disparity_range(ctx, *depth);
  const double shift = tri.principal_left_px().x - tri.principal_right_px().x;
  return PartnerColumns{left.x_px - shift - range.hi, left.x_px - shift - range.lo};
}

// Smallest row difference over all combinations, for the mismatch reason.
double closest_rows_px(const std::vector<Circle>& left, const std::vector<Circle>& right) {
  double best = std::numeric_limits<double>::infinity();
  for (const Circle& l : left)
    for (const Circle& r : right) best = std::min(best, std::abs(l.y_px - r.y_px));
  return best;
}

// Unsynchronised eyes: the ball moves between the two exposures by up to motion_radii of its
// radius, across as well as along the rows, so the disparity can miss the one its size implies
// by that much more than the size tolerance. Both eyes' radii are free of the timing (the depth
// hardly changes in the time): when they agree with each other (the caller checks) and the
// disparity is that far off at most, the pair is the ball, moved. Its position stays the
// triangulated one, rows averaged: on a real rig the radii are the less certain of the two
// (hands and seams pull the fits, the calibration's focal length and baseline err; the real
// basketball pairs' tune half has disparity and clicked radii disagreeing by up to 12 % on
// pairs without visible motion), and a disparity moved toward the size's depth was farther off.
void moved_ball(const PairingContext& ctx, double mean_radius_px, StereoPair& pair) {
  const stereo::Triangulator& tri = ctx.triangulator;
  const double tol = ctx.size.max_relative_error;
  const double size_disparity = tri.focal_px() * tri.baseline_m() / pair.depth_from_size_m;
  const double disparity = pair.left.x_px - pair.right.x_px;
  if (std::abs(disparity - size_disparity) >
      tol * size_disparity + ctx.motion_radii * mean_radius_px)
    return;
  pair.moved = true;
  pair.size_consistent = true;
}

}  // namespace

std::optional<PositionPrior> prior_from_track(const TrackedBall& track, std::int64_t frame_stamp_ns,
                                              double gate_m, std::int64_t max_age_ns) {
  if (!(gate_m > 0.0) || !track.following || !track.position_valid) return std::nullopt;
  const std::int64_t age_ns = frame_stamp_ns - track.capture_stamp_ns;
  if (age_ns > max_age_ns || age_ns < -max_age_ns) return std::nullopt;
  const double dt_s = 1e-9 * static_cast<double>(age_ns);
  return PositionPrior{track.position_m + track.velocity_mps * dt_s, gate_m, track.velocity_mps};
}

cv::Rect box_around(const cv::Point2d& centre, double reach_px, cv::Size image) {
  const cv::Point tl(static_cast<int>(std::floor(centre.x - reach_px)),
                     static_cast<int>(std::floor(centre.y - reach_px)));
  const cv::Point br(static_cast<int>(std::ceil(centre.x + reach_px)) + 1,
                     static_cast<int>(std::ceil(centre.y + reach_px)) + 1);
  return cv::Rect(tl, br) & cv::Rect(cv::Point(0, 0), image);
}

cv::Rect seed_box(const Circle& seed, double tolerance, cv::Size image) {
  const double reach =
      (1.0 + tolerance) * seed.radius_px + PixelToPixelParams::kPolishFirstBandPx + 2.0;
  return box_around({seed.x_px, seed.y_px}, reach, image);
}

Circle shifted(Circle c, cv::Point by) {
  c.x_px += by.x;
  c.y_px += by.y;
  return c;
}

cv::Rect prior_search_box(const PairingContext& ctx, const PositionPrior& prior, cv::Size image,
                          int margin_px) {
  // Off the axis the outline is an ellipse: its semi-major axis is the reach.
  const auto near = prior_near_outline(ctx, prior);
  if (!near) return {};
  const cv::Point2d centre = near->outline.centre_px;
  const double reach = (1.0 + ctx.size.max_relative_error) * near->outline.semi_major_px +
                       near->slack_px + static_cast<double>(margin_px);
  return box_around(centre, reach, image);
}

std::optional<ExpectedOutlines> prior_outlines(const PairingContext& ctx,
                                               const PositionPrior& prior) {
  const stereo::Triangulator& tri = ctx.triangulator;
  const double r_m = 0.5 * ctx.size.ball_diameter_m;
  const cv::Vec3d in_right = prior.position_m - cv::Vec3d(tri.baseline_m(), 0.0, 0.0);
  const auto left = stereo::sphere_outline(left_camera(tri), prior.position_m, r_m);
  const auto right = stereo::sphere_outline(right_camera(tri), in_right, r_m);
  if (!left || !right || !(prior.position_m[2] > r_m)) return std::nullopt;
  return ExpectedOutlines{
      Circle{left->centre_px.x, left->centre_px.y, left->mean_radius_px(), 0.0},
      Circle{right->centre_px.x, right->centre_px.y, right->mean_radius_px(), 0.0}};
}

RadiusRange prior_radius_range(const PairingContext& ctx, const PositionPrior& prior) {
  const double slack_m = prior_slack_m(prior);
  const double tol = ctx.size.max_relative_error;
  const auto near = prior_outline(ctx, prior, -slack_m);
  const auto far = prior_outline(ctx, prior, slack_m);
  // Without an outline (the prior at or behind the camera) nothing narrows the search.
  if (!near || !far) return {0.0, 1e9};
  return {far->semi_minor_px * (1.0 - tol) - 2.0, near->semi_major_px * (1.0 + tol) + 2.0};
}

RadiusRange partner_radius_range(const PairingContext& ctx, const std::vector<Circle>& left) {
  if (left.empty()) return {0.0, 1e9};
  const double tol = ctx.size.max_relative_error;
  RadiusRange r{1e9, 0.0};
  for (const Circle& c : left) {
    r.min_px = std::min(r.min_px, c.radius_px * (1.0 - tol) - 2.0);
    r.max_px = std::max(r.max_px, c.radius_px * (1.0 + tol) + 2.0);
  }
  return r;
}

bool better_pair(const StereoPair& a, const StereoPair& b) {
  if (a.score != b.score) return a.score > b.score;
  return a.row_residual_px < b.row_residual_px;
}

double row_allowance_px(const PairingContext& ctx, double radius_px) {
  return ctx.epipolar.params().max_row_diff_px + std::max(0.0, ctx.motion_radii) * radius_px;
}

std::optional<StereoPair> evaluate_pair(const PairingContext& ctx, const Circle& left,
                                        const Circle& right) {
  stereo::EpipolarMatch m = ctx.epipolar.check({left.x_px, left.y_px}, {right.x_px, right.y_px});
  const double mean_radius_px = 0.5 * (left.radius_px + right.radius_px);
  if (ctx.motion_radii > 0.0)
    m.accepted = m.row_residual_px <= row_allowance_px(ctx, mean_radius_px);
  // A point in front of the rig appears further left in the right eye.
  if (!m.accepted || m.x_left_px <= m.x_right_px) return std::nullopt;
  const double ball_radius_m = 0.5 * ctx.size.ball_diameter_m;
  auto p = ctx.triangulator.sphere_centre_m({left.x_px, left.y_px}, {right.x_px, right.y_px},
                                            ball_radius_m);
  if (!p || !((*p)[2] > 0.0)) return std::nullopt;

  StereoPair pair;
  pair.left = left;
  pair.right = right;
  pair.row_residual_px = m.row_residual_px;
  pair.position_m = *p;
  pair.score = 0.5 * (left.score + right.score);
  // Sizes as each eye sees the ball where it is: off the axis the outline is an ellipse whose
  // mean radius grows by up to 1 / cos^2 of the angle (24 % at 30 degrees), more than the
  // size tolerance.
  const stereo::Triangulator& tri = ctx.triangulator;
  const cv::Vec3d in_right = *p - cv::Vec3d(tri.baseline_m(), 0.0, 0.0);
  const auto depth_left = outline_depth_m(left_camera(tri), left, ball_radius_m);
  const auto depth_right = outline_depth_m(right_camera(tri), right, ball_radius_m);
  pair.depth_from_size_m = depth_left && depth_right ? 0.5 * (*depth_left + *depth_right) : 0.0;
  const double expected_px = 0.5 * (outline_radius_px(left_camera(tri), *p, ball_radius_m) +
                                    outline_radius_px(right_camera(tri), in_right, ball_radius_m));
  const stereo::SizeCheck size = stereo::check_size_against(ctx.size, mean_radius_px, expected_px);
  pair.expected_radius_px = size.expected_radius_px;
  pair.size_error = size.relative_error;
  pair.size_consistent = size.consistent;
  if (ctx.motion_radii > 0.0) {
    // With rows and disparity loosened by the motion, the two radii carry the check: both eyes
    // see the ball at nearly one depth (two round things that merely lie on nearby rows rarely
    // have one size).
    const double larger = std::max(left.radius_px, right.radius_px);
    const bool radii_agree =
        std::abs(left.radius_px - right.radius_px) <= ctx.size.max_relative_error * larger + 1.0;
    if (!radii_agree) pair.size_consistent = false;
    if (radii_agree && !pair.size_consistent && pair.depth_from_size_m > 0.0)
      moved_ball(ctx, mean_radius_px, pair);
  }
  if (ctx.floor) {
    pair.height_error_m = ctx.floor->height_m(*p) - ball_radius_m;
    pair.on_floor = std::abs(pair.height_error_m) <= ctx.floor->tolerance_m;
  }
  return pair;
}

cv::Rect partner_search_box(const PairingContext& ctx, const Circle& left, cv::Size image,
                            int margin_px) {
  const auto cols = partner_columns(ctx, left);
  if (!cols) return {};
  const double reach = (1.0 + ctx.size.max_relative_error) * left.radius_px + margin_px;
  // Unsynchronised eyes: the ball moved by up to motion_radii of its radius, any direction.
  const double moved = std::max(0.0, ctx.motion_radii) * left.radius_px;
  const double rows = reach + row_allowance_px(ctx, left.radius_px);
  const int x0 = static_cast<int>(std::floor(cols->x_near - reach - moved));
  const int x1 = static_cast<int>(std::ceil(cols->x_far + reach + moved)) + 1;
  const int y0 = static_cast<int>(std::floor(left.y_px - rows));
  const int y1 = static_cast<int>(std::ceil(left.y_px + rows)) + 1;
  return cv::Rect(cv::Point(x0, y0), cv::Point(x1, y1)) & cv::Rect(cv::Point(0, 0), image);
}

namespace {

// The left circle is the outline of one cone from the left camera; every sphere inscribed in it
// has its centre on the line of sight and a radius in proportion to its depth. With the ball's
// radius one depth fits; the others are the balls the size tolerance allows, and all touch the
// cone's top and bottom tangent planes, which contain the baseline: their right outlines lie
// on the left circle's rows, as the true ball's does.
struct LeftCone {
  cv::Vec3d dir;          ///< the line of sight of the centres, z = 1
  double depth_m = 0.0;   ///< of the ball-sized sphere in it
  double radius_m = 0.0;  ///< the ball's
};

// The right outline of the sphere inscribed in cone at depth z_m.
std::optional<Circle> right_outline_at(const stereo::Triangulator& tri, const LeftCone& cone,
                                       double z_m) {
  const cv::Vec3d in_right = cone.dir * z_m - cv::Vec3d(tri.baseline_m(), 0.0, 0.0);
  const double r_m = cone.radius_m * z_m / cone.depth_m;
  const auto o = stereo::sphere_outline(right_camera(tri), in_right, r_m);
  if (!o) return std::nullopt;
  return Circle{o->centre_px.x, o->centre_px.y, o->mean_radius_px(), 0.0};
}

// A right outline and the disparity it was made at.
struct OutlineAt {
  Circle outline;
  double disparity_px = 0.0;
};

// Outlines at the disparities d_hi, d_hi - step_px, ... down to d_lo (nearest ball first);
// at most kMaxOutlines + 1 of them (a coarser step for a wide range: each one is scored).
constexpr int kMaxOutlines = 256;

std::vector<OutlineAt> outlines_over(const stereo::Triangulator& tri, const LeftCone& cone,
                                     double d_lo, double d_hi, double step_px) {
  std::vector<OutlineAt> out;
  if (!(d_hi >= d_lo) || !(step_px > 0.0) || !std::isfinite(d_hi)) return out;
  step_px = std::max(step_px, (d_hi - d_lo) / kMaxOutlines);
  const double fb = tri.focal_px() * tri.baseline_m();
  const int steps = static_cast<int>(std::floor((d_hi - d_lo) / step_px + 1e-9));
  for (int i = 0; i <= steps; ++i) {
    const double d = d_hi - step_px * i;
    if (!(d > 0.0)) break;
    if (const auto c = right_outline_at(tri, cone, fb / d)) out.push_back({*c, d});
  }
  return out;
}

std::optional<LeftCone> left_cone(const PairingContext& ctx, const Circle& left) {
  const auto view = stereo::sphere_from_outline(left_camera(ctx.triangulator),
                                                {left.x_px, left.y_px}, left.radius_px);
  if (!view) return std::nullopt;
  const double r_m = 0.5 * ctx.size.ball_diameter_m;
  const double z = view->depth_m(r_m);
  if (!(z > 0.0)) return std::nullopt;
  const double t = view->tan_off_axis;
  return LeftCone{{t * view->major_axis.x, t * view->major_axis.y, 1.0}, z, r_m};
}

}  // namespace

std::vector<Circle> partner_outlines(const PairingContext& ctx, const Circle& left,
                                     double step_px) {
  const auto cone = left_cone(ctx, left);
  if (!cone || !(step_px > 0.0)) return {};
  const DisparityRange range = disparity_range(ctx, cone->depth_m);
  std::vector<Circle> out;
  for (const auto& o : outlines_over(ctx.triangulator, *cone, range.lo, range.hi, step_px))
    out.push_back(o.outline);
  return out;
}

namespace {

// The middle of the run of best-scoring outlines (they come in disparity order): a coverage
// score is flat over a pixel or more, most for a small far ball, and the first of the run
// would bias the depth toward the camera.
std::optional<OutlineAt> best_of(std::vector<OutlineAt> outlines, const OutlineScorer& score) {
  if (outlines.empty()) return std::nullopt;
  double best = -1.0;
  for (OutlineAt& o : outlines) {
    o.outline.score = score(o.outline);
    best = std::max(best, o.outline.score);
  }
  size_t first = 0;
  while (outlines[first].outline.score < best) ++first;
  size_t last = first;
  while (last + 1 < outlines.size() && outlines[last + 1].outline.score >= best) ++last;
  return outlines[(first + last) / 2];
}

// Whether a ball in cone, at a depth the disparity range allows, can rest on the floor (twice
// the floor tolerance: the pair triangulates a little off the cone's axis). The height of a
// point on the line of sight is linear in its depth, so the range's ends bound it.
bool may_rest_on_floor(const PairingContext& ctx, const LeftCone& cone,
                       const DisparityRange& range) {
  if (!ctx.floor) return true;
  const double fb = ctx.triangulator.focal_px() * ctx.triangulator.baseline_m();
  const double z_near = fb / range.hi;
  const double z_far = range.lo > 0.0 ? fb / range.lo : 1e3;
  const double e_near = ctx.floor->height_m(cone.dir * z_near) - cone.radius_m;
  const double e_far = ctx.floor->height_m(cone.dir * z_far) - cone.radius_m;
  const double slack = 2.0 * ctx.floor->tolerance_m;
  return std::min(e_near, e_far) <= slack && std::max(e_near, e_far) >= -slack;
}

}  // namespace

std::optional<RadiusBalance> radius_balance(const stereo::Triangulator& tri, const Circle& left,
                                            const Circle& right, const cv::Vec3d& position_m,
                                            double ball_radius_m, double min_px, double fraction) {
  const double expected_left = outline_radius_px(left_camera(tri), position_m, ball_radius_m);
  const cv::Vec3d in_right = position_m - cv::Vec3d(tri.baseline_m(), 0.0, 0.0);
  const double expected_right = outline_radius_px(right_camera(tri), in_right, ball_radius_m);
  if (!(expected_left > 0.0) || !(expected_right > 0.0)) return std::nullopt;
  // The left radius as the right eye would see it.
  const double left_seen_right = left.radius_px * expected_right / expected_left;
  const double difference = left_seen_right - right.radius_px;
  if (std::abs(difference) <= std::max(min_px, fraction * right.radius_px)) return std::nullopt;
  if (difference > 0.0) return RadiusBalance{true, left_seen_right};
  return RadiusBalance{false, right.radius_px * expected_left / expected_right};
}

std::optional<Circle> predicted_partner(const PairingContext& ctx, const Circle& left,
                                        const OutlineScorer& score, double min_score) {
  const auto cone = left_cone(ctx, left);
  if (!cone) return std::nullopt;
  const DisparityRange range = disparity_range(ctx, cone->depth_m);
  // A pair off the floor fails the floor check whatever the right eye holds: not worth the
  // scoring (in clutter most left circles are such).
  if (!may_rest_on_floor(ctx, *cone, range)) return std::nullopt;
  const auto coarse =
      best_of(outlines_over(ctx.triangulator, *cone, range.lo, range.hi, 1.0), score);
  if (!coarse || coarse->outline.score < min_score) return std::nullopt;
  // A finer pass centres the outline on the rim.
  const double d = coarse->disparity_px;
  const auto fine = best_of(
      outlines_over(ctx.triangulator, *cone, std::max(0.25, d - 1.0), d + 1.0, 0.25), score);
  if (!fine || fine->outline.score < coarse->outline.score) return coarse->outline;
  return fine->outline;
}

int prior_centre_margin_px(const PairingContext& ctx, const PositionPrior& prior, cv::Size image) {
  const auto near = prior_near_outline(ctx, prior);
  if (!near) return 0;
  return margin_cap_px(outside_by_px(near->outline.centre_px, near->slack_px, image),
                       (1.0 + ctx.size.max_relative_error) * near->outline.semi_major_px);
}

int partner_centre_margin_px(const PairingContext& ctx, const std::vector<Circle>& left,
                             cv::Size image) {
  int margin = 0;
  const double rows = ctx.epipolar.params().max_row_diff_px;
  for (const Circle& c : left) {
    const auto cols = partner_columns(ctx, c);
    if (!cols) continue;
    const double cap = (1.0 + ctx.size.max_relative_error) * c.radius_px;
    for (const double x : {cols->x_near, cols->x_far})
      margin = std::max(margin, margin_cap_px(outside_by_px({x, c.y_px}, rows, image), cap));
  }
  return margin;
}

bool prefer_unmoved(const PairingContext& ctx, const StereoPair& unmoved, const StereoPair& best) {
  if (!(ctx.dominance_margin > 0.0) || !best.moved || unmoved.moved) return false;
  return unmoved.score >= best.score - ctx.dominance_margin &&
         unmoved.left.radius_px + unmoved.right.radius_px >
             best.left.radius_px + best.right.radius_px;
}

std::optional<StereoPair> dominating_pair(const PairingContext& ctx, const StereoPair& found,
                                          const std::vector<StereoPair>& size_rejected) {
  // The rule stands for unsynchronised eyes only: a synchronised rig's rows and disparity
  // leave the ball no way to fail the size check by moving.
  if (!(ctx.dominance_margin > 0.0) || !(ctx.motion_radii > 0.0)) return std::nullopt;
  const double found_radius = 0.5 * (found.left.radius_px + found.right.radius_px);
  std::optional<StereoPair> best;
  for (const StereoPair& p : size_rejected) {
    const double larger = std::max(p.left.radius_px, p.right.radius_px);
    const bool radii_agree = std::abs(p.left.radius_px - p.right.radius_px) <=
                             ctx.size.max_relative_error * larger + 1.0;
    // Another view of the found pair's own outlines is no rival.
    const bool shares = p.left_index == found.left_index || p.right_index == found.right_index;
    if (!radii_agree || shares || p.score < found.score + ctx.dominance_margin ||
        0.5 * (p.left.radius_px + p.right.radius_px) < found_radius)
      continue;
    if (!best || better_pair(p, *best)) best = p;
  }
  return best;
}

namespace {

// The running bests of one frame's pair evaluation.
struct PairTally {
  std::optional<StereoPair> ok;          // best size-consistent pair on the floor
  std::optional<StereoPair> near_prior;  // of those, best within the prior's gate
  // Closest to consistent, for the reason text: off the floor (the size fits) beats wrong size.
  std::optional<StereoPair> off_floor;
  std::optional<StereoPair> rejected;
  std::vector<StereoPair> size_rejected;  // kept only with a dominance margin
  std::optional<StereoPair> unmoved;      // best size-consistent pair that needed no motion
};

// Files one pair that passed the row check into the tally and out's counts.
void tally_pair(const PairingContext& ctx, const std::optional<PositionPrior>& prior,
                const StereoPair& pair, PairTally& t, PairingResult& out) {
  ++out.row_matches;
  if (!pair.size_consistent) {
    if (ctx.dominance_margin > 0.0 && ctx.motion_radii > 0.0) t.size_rejected.push_back(pair);
    if (!t.rejected || std::abs(pair.size_error) < std::abs(t.rejected->size_error))
      t.rejected = pair;
    return;
  }
  ++out.size_matches;
  if (!pair.on_floor) {
    if (!t.off_floor || std::abs(pair.height_error_m) < std::abs(t.off_floor->height_error_m))
      t.off_floor = pair;
    return;
  }
  if (!t.ok || better_pair(pair, *t.ok)) t.ok = pair;
  if (!pair.moved && (!t.unmoved || better_pair(pair, *t.unmoved))) t.unmoved = pair;
  if (prior && cv::norm(pair.position_m - prior->position_m) <= prior->gate_m &&
      (!t.near_prior || better_pair(pair, *t.near_prior)))
    t.near_prior = pair;
}

// Every left/right combination evaluated and tallied.
PairTally tally_pairs(const PairingContext& ctx, const std::vector<Circle>& left,
                      const std::vector<Circle>& right, const std::optional<PositionPrior>& prior,
                      PairingResult& out) {
  PairTally t;
  for (std::size_t i = 0; i < left.size(); ++i) {
    for (std::size_t j = 0; j < right.size(); ++j) {
      auto pair = evaluate_pair(ctx, left[i], right[j]);
      if (!pair) continue;
      pair->left_index = i;
      pair->right_index = j;
      tally_pair(ctx, prior, *pair, t, out);
    }
  }
  return t;
}

// The pair to report among the size-consistent ones: near the prior, else the best (or the
// unmoved one the dominance rule prefers).
std::optional<StereoPair> chosen_pair(const PairingContext& ctx, const PairTally& t) {
  if (t.near_prior) return t.near_prior;
  if (t.ok && t.unmoved && prefer_unmoved(ctx, *t.unmoved, *t.ok)) return t.unmoved;
  return t.ok;
}

// The result for a frame with a chosen pair: withdrawn when a stronger size-rejected pair
// dominates it (never near a track's prior: the followed ball is the answer there).
PairingResult found_result(const PairingContext& ctx, const StereoPair& chosen, const PairTally& t,
                           PairingResult out) {
  const auto strong = t.near_prior ? std::nullopt : dominating_pair(ctx, chosen, t.size_rejected);
  if (strong) {
    out.status = PairingStatus::kSizeInconsistent;
    out.best = strong;
    out.reason =
        format("stronger outlines (score %.2f, radius %.1f px, rows %.1f px apart) pair at a ",
               strong->score, 0.5 * (strong->left.radius_px + strong->right.radius_px),
               strong->row_residual_px) +
        format(
            "disparity their size does not fit; the weaker size-consistent pair (score "
            "%.2f, radius %.1f px) is not reported",
            chosen.score, 0.5 * (chosen.left.radius_px + chosen.right.radius_px));
    return out;
  }
  out.status = PairingStatus::kFound;
  out.best = chosen;
  out.reason = format("pair score %.2f, row residual %.2f px, disparity %.1f px", chosen.score,
                      chosen.row_residual_px, chosen.left.x_px - chosen.right.x_px);
  return out;
}

// The result for a frame without a size-consistent pair on the floor: the closest rejection.
PairingResult rejected_result(const PairingContext& ctx, const std::vector<Circle>& left,
                              const std::vector<Circle>& right, const PairTally& t,
                              PairingResult out) {
  if (t.off_floor) {
    const StereoPair& p = *t.off_floor;
    out.status = PairingStatus::kOffFloor;
    out.best = t.off_floor;
    out.reason = format("ball-sized pair %.2f m ", std::abs(p.height_error_m)) +
                 (p.height_error_m > 0.0 ? "above" : "below") +
                 format(" where a ball on the floor is (tolerance %.2f m), %.2f m away",
                        ctx.floor->tolerance_m, p.position_m[2]);
    return out;
  }
  if (t.rejected) {
    const StereoPair& p = *t.rejected;
    out.status = PairingStatus::kSizeInconsistent;
    out.best = t.rejected;
    out.reason = format("radius %.1f px but a ball at %.2f m should be %.1f px (error %+.0f%%)",
                        0.5 * (p.left.radius_px + p.right.radius_px), p.position_m[2],
                        p.expected_radius_px, 100.0 * p.size_error);
    return out;
  }
  out.status = PairingStatus::kEpipolarMismatch;
  if (ctx.motion_radii > 0.0) {
    out.reason = format(
        "no pair in front of the rig within %.1f px rows plus %.2f of its radius (the ball's "
        "motion between the exposures; closest rows differ by %.1f px)",
        ctx.epipolar.params().max_row_diff_px, ctx.motion_radii, closest_rows_px(left, right));
    return out;
  }
  out.reason =
      format("no pair in front of the rig within %.1f px rows (closest rows differ by %.1f px)",
             ctx.epipolar.params().max_row_diff_px, closest_rows_px(left, right));
  return out;
}

}  // namespace

PairingResult pair_candidates(const PairingContext& ctx, const std::vector<Circle>& left,
                              const std::vector<Circle>& right,
                              const std::optional<PositionPrior>& prior) {
  PairingResult out;
  if (left.empty() || right.empty()) {
    out.status = PairingStatus::kNoCandidate;
    out.reason = no_candidate_reason(left.empty(), right.empty());
    return out;
  }
  const PairTally t = tally_pairs(ctx, left, right, prior, out);
  if (const auto chosen = chosen_pair(ctx, t)) return found_result(ctx, *chosen, t, out);
  return rejected_result(ctx, left, right, t, out);
}

}  // namespace stereoball::ball_detector
