// StereoPipeline::refit_outlines (a found pair's outlines fitted again to the arcs that agree) and
// check_moved_pair (a pair that needs the motion allowance checked for one ball's outlines);
// outline_refit.hpp.

#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace stereoball::ball_detector {

namespace {

// True for a pair the paper's rules would refuse, its rows or its disparity needing the
// motion allowance, and only while that allowance is on.
bool needs_motion_allowance(const PairingContext& ctx, const StereoPair& pair) {
  const double tolerance_px = ctx.epipolar.params().max_row_diff_px;
  // Written as the negation of the accepting test so that a NaN residual counts as needing it.
  return ctx.motion_radii > 0.0 && !(pair.row_residual_px <= tolerance_px && !pair.moved);
}

}  // namespace

std::optional<Circle> StereoPipeline::robust_outline_in(const cv::Mat& channel, stereo::Eye eye,
                                                        bool rectified, const Circle& circle) {
  const OutlineSearchParams& search = tools_.params.outline_refit.search;
  // Every hypothesis's outline and band, and the edge step's window beyond it.
  const int margin = static_cast<int>(std::ceil((1.0 + search.radius_slack + search.centre_slack +
                                                 search.band_per_radius) *
                                                    circle.radius_px +
                                                search.band_px)) +
                     tools_.window_margin_px();
  const std::optional<cv::Rect> found_region =
      edges_around(channel, eye, rectified, circle, margin);
  if (!found_region) return std::nullopt;
  const cv::Rect region = *found_region;
  const auto found = robust_outline(balance_edges_, shifted(circle, -region.tl()), search);
  if (!found) return std::nullopt;
  return shifted(*found, region.tl());
}

void StereoPipeline::refit_outlines(const FrameState& frame, StereoDetection& found) {
  const auto left =
      robust_outline_in(frame.left_channel, stereo::Eye::kLeft, frame.rectified, found.left);
  const auto right =
      robust_outline_in(frame.right_channel, stereo::Eye::kRight, frame.rectified, found.right);
  if (!left || !right) return;
  // The pair keeps its scores: the refit measures coverage in a narrower band.
  Circle l = *left, r = *right;
  l.score = found.left.score;
  r.score = found.right.score;
  const RefitVerdict v = judge_refit(frame.ctx, found.left, found.right, l, r);
  if (!v.changed) return;
  if (v.pair) {
    found.left = v.pair->left;
    found.right = v.pair->right;
    found.row_residual_px = v.pair->row_residual_px;
    found.position_m = v.pair->position_m;
    found.depth_from_size_m = v.pair->depth_from_size_m;
    found.reason += "; " + v.note;
  } else if (tools_.params.outline_refit.withdraw_unpaired) {
    found.status = DetectionStatus::kSizeInconsistent;
    found.reason = v.note + " (first paired: " + found.reason + ")";
  }
}

void StereoPipeline::check_moved_pair(const FrameState& frame, const StereoPair& paired,
                                      StereoDetection& found) {
  const PairingContext& ctx = frame.ctx;
  if (!needs_motion_allowance(ctx, paired)) return;
  const double tolerance_px = ctx.epipolar.params().max_row_diff_px;
  const MovedRadii radii = moved_radii(ctx, paired);
  if (radii.agree) return;
  // One eye's fit is off, or the eyes saw two things. The pair stands if an eye's outline is
  // found again, from the other eye's circle, where the ball would be had it not moved.
  double closest_px = std::numeric_limits<double>::infinity();
  for (const bool from_right : {true, false}) {
    const Circle& own = from_right ? paired.left : paired.right;
    const auto predicted =
        unmoved_partner_outline(ctx, from_right ? paired.right : paired.left, from_right);
    if (!predicted) continue;
    const auto refit = robust_outline_in(from_right ? frame.left_channel : frame.right_channel,
                                         from_right ? stereo::Eye::kLeft : stereo::Eye::kRight,
                                         frame.rectified, *predicted);
    if (!refit) continue;
    const double off_px = std::hypot(refit->x_px - own.x_px, refit->y_px - own.y_px);
    if (off_px <= std::max(tolerance_px, ctx.size.max_relative_error * own.radius_px)) return;
    closest_px = std::min(closest_px, off_px);
  }
  char text[360];
  std::snprintf(text, sizeof text,
                "the eyes' outlines (left r %.1f, right r %.1f px, rows %.1f px apart) are not "
                "one ball's: their radii differ by %.2f px, more than the ball's motion between "
                "the exposures explains (%.2f px), and neither eye's outline is found again "
                "where the other's puts the ball (closest %.0f px away)",
                paired.left.radius_px, paired.right.radius_px, paired.row_residual_px,
                radii.difference_px, radii.allowed_px, closest_px);
  found.status = DetectionStatus::kSizeInconsistent;
  found.reason = std::string(text) + " (first paired: " + found.reason + ")";
}

void StereoPipeline::check_interior_motion(const FrameState& frame, const StereoPair& paired,
                                           StereoDetection& found) {
  const PairingContext& ctx = frame.ctx;
  if (!needs_motion_allowance(ctx, paired)) return;
  const double tolerance_px = ctx.epipolar.params().max_row_diff_px;
  const Circle& l = found.left;
  const Circle& r = found.right;
  const double circle_dy = l.y_px - r.y_px;
  // The inside is looked for wherever the ball can have moved to (the motion allowance) from
  // where the outlines put it; the reaches bound the search, not the verdict.
  const double reach = ctx.motion_radii * 0.5 * (l.radius_px + r.radius_px) + tolerance_px;
  const double dy_reach = reach, dx_reach = reach;
  // The regions interior_offset reads: the inner square around each circle's centre, the
  // right one grown by the reaches.
  const auto around = [](const Circle& c, double half_w, double half_h) {
    return cv::Rect(static_cast<int>(std::floor(c.x_px - half_w)),
                    static_cast<int>(std::floor(c.y_px - half_h)),
                    static_cast<int>(std::ceil(2.0 * half_w)) + 2,
                    static_cast<int>(std::ceil(2.0 * half_h)) + 2);
  };
  const InteriorOffsetParams offset_params;
  const double half = offset_params.inner_fraction * l.radius_px + 2.0;
  const cv::Rect img(cv::Point(), tools_.image_size());
  const cv::Rect lbox = around(l, half, half) & img;
  const cv::Rect rbox = around(r, half + dx_reach + 2.0, half + dy_reach + 2.0) & img;
  if (lbox.empty() || rbox.empty()) return;
  const cv::Mat& li =
      rectified_region(frame.left_channel, stereo::Eye::kLeft, frame.rectified, lbox);
  const cv::Mat& ri =
      rectified_region(frame.right_channel, stereo::Eye::kRight, frame.rectified, rbox);
  const InteriorOffset o = interior_offset(li, ri, l, r, dx_reach, dy_reach, offset_params);
  if (!o.measured) return;
  // The outlines' rows and the inside's each err by up to the paper's tolerance.
  if (!(std::abs(circle_dy) > std::abs(o.dy_px) + 2.0 * tolerance_px)) return;
  char text[360];
  std::snprintf(text, sizeof text,
                "the outlines' rows differ by %.1f px but the inside of the ball by %.1f px "
                "(matched between the eyes, correlation %.2f): the ball did not move that much "
                "between the exposures, the outline fits are off",
                circle_dy, o.dy_px, o.match);
  found.status = DetectionStatus::kEpipolarMismatch;
  found.reason = std::string(text) + " (first paired: " + found.reason + ")";
}

}  // namespace stereoball::ball_detector
