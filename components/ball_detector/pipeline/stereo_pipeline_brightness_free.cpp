// StereoPipeline's last resort for a hue-only rim: the colour seeds' outlines, or a track's
// expected outline, searched again on the images with their brightness removed (edge_map.hpp,
// compute_brightness_free_edge_map).

#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"

namespace stereoball::ball_detector {

std::optional<Circle> StereoPipeline::right_outline_without_brightness(
    const PairingContext& ctx, const cv::Mat& right_channel, bool rectified, const Circle& left,
    const EdgeThresholds& thresholds) {
  const cv::Rect box =
      partner_search_box(ctx, left, rectifier_->calibration().image_size, window_margin_px());
  if (box.width < 8 || box.height < 8 || right_channel.type() != CV_8UC3) return std::nullopt;
  if (rect_right_.size() != rectifier_->calibration().image_size ||
      rect_right_.type() != right_channel.type())
    clear_rectified(right_channel, rect_right_);
  rectify_box(right_channel, stereo::Eye::kRight, rectified, box, rect_right_);
  // The left box's thresholds: the partner box is mostly floor, and its own statistics would
  // depend on how much of it the ball covers.
  const PixelToPixelParams p2p = params_.detector_params();
  compute_brightness_free_edge_map(rect_right_(box), p2p.edge, thresholds.canny, thresholds.denoise,
                                   brightness_free_right_, partner_edges_);
  // As away from a track (the search near a prior gets no laxer border rule here).
  return partner_on_edges(ctx, left, partner_edges_, box.tl(),
                          partner_scoring(partner_min_inside_fraction(false)));
}

PairingResult StereoPipeline::pair_seeds_without_brightness(
    const PairingContext& ctx, const cv::Mat& left_channel, const cv::Mat& right_channel,
    bool rectified, const std::optional<PositionPrior>& prior, std::span<const Circle> seeds) {
  left_candidates_.clear();
  right_candidates_.clear();
  const cv::Size size = rectifier_->calibration().image_size;
  const SearchHints hints{left_detector_.radius_range()};
  if (left_channel.type() != CV_8UC3 || rect_left_.size() != size ||
      rect_left_.type() != left_channel.type())
    return pair_candidates(ctx, left_candidates_, right_candidates_, prior);
  for (const Circle& seed : seeds) {
    const cv::Rect box = seed_box(seed, size_.max_relative_error, size);
    if (box.width < 8 || box.height < 8) continue;
    // A search near the prior rectified its own box only.
    rectify_box(left_channel, stereo::Eye::kLeft, rectified, box, rect_left_);
    const Circle seed_in_box = shifted(seed, -box.tl());
    for (const Circle& c : seed_detector_.detect_at_seeds_without_brightness(rect_left_(box), hints,
                                                                             {&seed_in_box, 1})) {
      const Circle left = shifted(c, box.tl());
      const auto right = right_outline_without_brightness(ctx, right_channel, rectified, left,
                                                          thresholds_of(seed_detector_.edge_map()));
      if (!right) continue;
      left_candidates_.push_back(left);
      right_candidates_.push_back(*right);
    }
  }
  rejected_by_colour_ += apply_appearance();
  return pair_candidates(ctx, left_candidates_, right_candidates_, prior);
}

std::optional<PairingResult> StereoPipeline::pair_expected_without_brightness(
    const PairingContext& ctx, const cv::Mat& left_channel, const cv::Mat& right_channel,
    bool rectified, const PositionPrior& prior) {
  const auto expected = prior_outlines(ctx, prior);
  if (!expected) return std::nullopt;
  PairingResult pairing = pair_seeds_without_brightness(ctx, left_channel, right_channel, rectified,
                                                        prior, {&expected->left, 1});
  if (pairing.status == PairingStatus::kFound &&
      cv::norm(pairing.best->position_m - prior.position_m) <= prior.gate_m)
    return pairing;
  return std::nullopt;
}

}  // namespace stereoball::ball_detector
