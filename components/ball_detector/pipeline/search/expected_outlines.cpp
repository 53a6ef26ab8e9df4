#include "ball_detector/pipeline/search/expected_outlines.hpp"

namespace stereoball::ball_detector {

std::optional<SearchOutcome> ExpectedOutlinesSearch::run(const FrameState& frame,
                                                         FrameScratch& scratch,
                                                         SearchTools& tools) const {
  if (!tools.params.prior_seeded) return std::nullopt;
  const PositionPrior& prior = *frame.prior;
  const auto expected = prior_outlines(frame.ctx, prior);
  if (!expected) return std::nullopt;
  const cv::Rect left_box = scratch.prior_box;
  const Circle left_seed = shifted(expected->left, -left_box.tl());
  std::vector<Circle> left;
  for (const Circle& c : tools.left_detector.detect_at_seeds(
           tools.rect_left(left_box), *tools.left_thresholds, scratch.prior_hints, {&left_seed, 1}))
    left.push_back(shifted(c, left_box.tl()));
  if (left.empty()) return std::nullopt;
  // The prediction errs alike in both eyes: the right seed is the left circle found, moved as
  // the expected outline moves from eye to eye.
  const Circle& first = left.front();
  const Circle right_seed{first.x_px + expected->right.x_px - expected->left.x_px,
                          first.y_px + expected->right.y_px - expected->left.y_px,
                          first.radius_px * expected->right.radius_px / expected->left.radius_px,
                          0.0};
  const cv::Rect box = seed_box(right_seed, frame.ctx.size.max_relative_error, tools.image_size());
  if (box.width < 8 || box.height < 8) return std::nullopt;
  tools.clear_rectified(frame.right_channel, tools.rect_right);
  tools.rectify_box(frame.right_channel, stereo::Eye::kRight, frame.rectified, box,
                    tools.rect_right);
  tools.right_edges_box = box;
  const SearchHints right_hints{partner_radius_range(frame.ctx, left),
                                tools.params.prior_min_inside_fraction};
  const Circle seed_in_box = shifted(right_seed, -box.tl());
  std::vector<Circle> right;
  for (const Circle& c : tools.right_detector.detect_at_seeds(
           tools.rect_right(box), *tools.left_thresholds, right_hints, {&seed_in_box, 1}))
    right.push_back(shifted(c, box.tl()));
  SearchOutcome out = pairing_.pair(frame, tools, std::move(left), std::move(right), true);
  if (!out.found_near(prior)) return std::nullopt;
  out.path = SearchPath::kExpectedOutlines;
  return out;
}

}  // namespace stereoball::ball_detector
