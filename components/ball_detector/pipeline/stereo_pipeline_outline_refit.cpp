// StereoPipeline::refit_outlines: a found pair's outlines fitted again to the arcs that agree
// (outline_refit.hpp).

#include "ball_detector/pipeline/stereo_pipeline.hpp"

#include <cmath>

namespace stereoball::ball_detector {

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

}  // namespace stereoball::ball_detector
