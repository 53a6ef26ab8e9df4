#include "ball_detector/pipeline/search/prior_window.hpp"

namespace stereoball::ball_detector {

bool prepare_prior_box(const FrameState& frame, FrameScratch& scratch, SearchTools& tools) {
  const cv::Size size = tools.image_size();
  const PositionPrior& prior = *frame.prior;
  const cv::Rect box = prior_search_box(frame.ctx, prior, size, tools.window_margin_px());
  if (box.width < 8 || box.height < 8) return false;
  tools.clear_rectified(frame.left_channel, tools.rect_left);
  tools.rectify_box(frame.left_channel, stereo::Eye::kLeft, frame.rectified, box, tools.rect_left);
  scratch.prior_box = box;
  // The tracker expects the ball here: a ball it follows out of the view is still scored on
  // what is left of it in the image, and may have its centre outside the image.
  scratch.prior_hints =
      SearchHints{prior_radius_range(frame.ctx, prior), tools.params.prior_min_inside_fraction};
  scratch.prior_hints.centre_margin_px = prior_centre_margin_px(frame.ctx, prior, size);
  return true;
}

std::optional<SearchOutcome> PriorWindowSearch::run(const FrameState& frame, FrameScratch& scratch,
                                                    SearchTools& tools) const {
  const cv::Rect box = scratch.prior_box;
  std::vector<Circle> left;
  for (const Circle& c : tools.left_detector.detect(tools.rect_left(box), *tools.left_thresholds,
                                                    scratch.prior_hints))
    left.push_back(shifted(c, box.tl()));
  std::vector<Circle> right = tools.detect_right_in_boxes(frame, left, true);
  SearchOutcome out = pairing_.pair(frame, tools, std::move(left), std::move(right), true);
  out.path = SearchPath::kPriorWindow;
  return out;
}

}  // namespace stereoball::ball_detector
