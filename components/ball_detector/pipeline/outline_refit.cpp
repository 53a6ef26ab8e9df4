#include "ball_detector/pipeline/outline_refit.hpp"

#include <cstdio>

namespace stereoball::ball_detector {
namespace {

bool same_circle(const Circle& a, const Circle& b) {
  return a.x_px == b.x_px && a.y_px == b.y_px && a.radius_px == b.radius_px;
}

}  // namespace

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
