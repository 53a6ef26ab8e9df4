#include "ball_detector/pipeline/search/brightness_free.hpp"

#include "ball_detector/core/edge_map.hpp"

namespace stereoball::ball_detector {

std::optional<SearchOutcome> BrightnessFreeSearch::run(const FrameState& frame,
                                                       FrameScratch& scratch,
                                                       SearchTools& tools) const {
  if (!tools.params.colour_seeds.chroma_outlines) return std::nullopt;
  SearchOutcome out;
  if (seeds_ == BrightnessFreeSeeds::kColourSeeds) {
    if (scratch.colour_seeds.empty()) return std::nullopt;
    out = pair_seeds(frame, tools, scratch.colour_seeds);
  } else {
    const auto expected = prior_outlines(frame.ctx, *frame.prior);
    if (!expected) return std::nullopt;
    out = pair_seeds(frame, tools, {&expected->left, 1});
  }
  out.path = SearchPath::kBrightnessFree;
  return out;
}

SearchOutcome BrightnessFreeSearch::pair_seeds(const FrameState& frame, SearchTools& tools,
                                               std::span<const Circle> seeds) const {
  SearchOutcome out;
  const cv::Size size = tools.image_size();
  const SearchHints hints{tools.left_detector.radius_range()};
  if (frame.left_channel.type() != CV_8UC3 || tools.rect_left.size() != size ||
      tools.rect_left.type() != frame.left_channel.type()) {
    out.pairing = pair_candidates(frame.ctx, out.left, out.right, frame.prior);
    return out;
  }
  for (const Circle& seed : seeds) {
    const cv::Rect box = seed_box(seed, frame.ctx.size.max_relative_error, size);
    if (box.width < 8 || box.height < 8) continue;
    // A search near the prior rectified its own box only.
    tools.rectify_box(frame.left_channel, stereo::Eye::kLeft, frame.rectified, box,
                      tools.rect_left);
    const Circle seed_in_box = shifted(seed, -box.tl());
    for (const Circle& c : tools.seed_detector.detect_at_seeds_without_brightness(
             tools.rect_left(box), hints, {&seed_in_box, 1})) {
      const Circle left = shifted(c, box.tl());
      const auto right =
          right_outline(frame, tools, left, thresholds_of(tools.seed_detector.edge_map()));
      if (!right) continue;
      out.left.push_back(left);
      out.right.push_back(*right);
    }
  }
  out.rejected_by_colour = tools.apply_appearance(frame, out.left);
  out.pairing = pair_candidates(frame.ctx, out.left, out.right, frame.prior);
  return out;
}

std::optional<Circle> BrightnessFreeSearch::right_outline(const FrameState& frame,
                                                          SearchTools& tools, const Circle& left,
                                                          const EdgeThresholds& thresholds) const {
  const cv::Size size = tools.image_size();
  const cv::Rect box = partner_search_box(frame.ctx, left, size, tools.window_margin_px());
  if (box.width < 8 || box.height < 8 || frame.right_channel.type() != CV_8UC3) return std::nullopt;
  if (tools.rect_right.size() != size || tools.rect_right.type() != frame.right_channel.type())
    tools.clear_rectified(frame.right_channel, tools.rect_right);
  tools.rectify_box(frame.right_channel, stereo::Eye::kRight, frame.rectified, box,
                    tools.rect_right);
  // The left box's thresholds: the partner box is mostly floor, and its own statistics would
  // depend on how much of it the ball covers.
  const PixelToPixelParams p2p = tools.params.detector_params();
  compute_brightness_free_edge_map(tools.rect_right(box), p2p.edge, thresholds.canny,
                                   thresholds.denoise, tools.brightness_free_right,
                                   tools.partner_edges);
  // As away from a track (the search near a prior gets no laxer border rule here).
  return tools.partner_on_edges(frame.ctx, left, tools.partner_edges, box.tl(),
                                tools.partner_scoring(tools.partner_min_inside_fraction(false)));
}

}  // namespace stereoball::ball_detector
