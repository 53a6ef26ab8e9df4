#include "ball_detector/pipeline/search/predicted_partner.hpp"

#include "ball_detector/core/edge_map.hpp"

namespace stereoball::ball_detector {

SearchOutcome PredictedPartner::pair(const FrameState& frame, SearchTools& tools,
                                     std::vector<Circle> left, std::vector<Circle> right,
                                     bool near_prior) const {
  SearchOutcome out;
  out.left = std::move(left);
  out.right = std::move(right);
  out.rejected_by_colour = tools.apply_appearance(frame, out.left);
  out.pairing = pair_candidates(frame.ctx, out.left, out.right, frame.prior);
  if (!tools.params.predicted_partner || out.found()) return out;
  // The left circle passed its own border rule; the right eye sees the ball shifted by the
  // disparity, often farther out of the image, and its outline has one free parameter left:
  // a smaller part in view suffices, near a track's prior only (README: predicted partner).
  const auto predicted =
      partners(frame.ctx, tools, out.left, tools.partner_min_inside_fraction(near_prior));
  if (predicted.empty()) return out;
  out.right.insert(out.right.end(), predicted.begin(), predicted.end());
  out.pairing = pair_candidates(frame.ctx, out.left, out.right, frame.prior);
  return out;
}

std::vector<Circle> PredictedPartner::partners(const PairingContext& ctx, SearchTools& tools,
                                               const std::vector<Circle>& left,
                                               double min_inside_fraction) const {
  const cv::Size size = tools.image_size();
  const EdgeThresholds thresholds = thresholds_of(tools.left_detector.edge_map());
  const PixelToPixelParams p2p = tools.params.detector_params();
  const RefineParams scoring = tools.partner_scoring(min_inside_fraction);
  std::vector<Circle> found;
  for (const Circle& c : left) {
    const cv::Rect box = partner_search_box(ctx, c, size, tools.window_margin_px());
    if (box.width < 8 || box.height < 8) continue;
    // The search rectified this box already (it searched the union of these), and the right
    // detector still holds the edges of the last box it searched.
    const EdgeMap* edges = &tools.right_detector.edge_map();
    cv::Point origin = tools.right_edges_box.tl();
    if ((box & tools.right_edges_box) != box) {
      compute_edge_map(tools.rect_right(box), p2p.edge, thresholds.canny, thresholds.denoise,
                       tools.partner_edges);
      edges = &tools.partner_edges;
      origin = box.tl();
    }
    if (auto partner = tools.partner_on_edges(ctx, c, *edges, origin, scoring))
      found.push_back(*partner);
  }
  return found;
}

}  // namespace stereoball::ball_detector
