#include "ball_detector/core/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace stereoball::ball_detector {

double circle_iou(const Circle& a, const Circle& b) {
  const double r1 = a.radius_px, r2 = b.radius_px;
  if (r1 <= 0.0 || r2 <= 0.0) return 0.0;
  const double d = std::hypot(a.x_px - b.x_px, a.y_px - b.y_px);
  const double a1 = std::numbers::pi * r1 * r1, a2 = std::numbers::pi * r2 * r2;
  double inter = 0.0;
  if (d >= r1 + r2) {
    inter = 0.0;
  } else if (d <= std::abs(r1 - r2)) {
    inter = std::min(a1, a2);
  } else {
    // Lens area: two circular segments.
    const double c1 = std::clamp((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1), -1.0, 1.0);
    const double c2 = std::clamp((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2), -1.0, 1.0);
    const double t1 = std::acos(c1), t2 = std::acos(c2);
    inter = r1 * r1 * (t1 - std::sin(2.0 * t1) / 2.0) + r2 * r2 * (t2 - std::sin(2.0 * t2) / 2.0);
  }
  return inter / (a1 + a2 - inter);
}

MatchResult match_circles(const std::vector<Circle>& detections, const std::vector<Circle>& truth,
                          double min_iou) {
  std::vector<Circle> dets = detections;
  std::stable_sort(dets.begin(), dets.end(),
                   [](const Circle& a, const Circle& b) { return a.score > b.score; });
  std::vector<bool> used(truth.size(), false);
  MatchResult r;
  for (const auto& d : dets) {
    int best = -1;
    double best_iou = min_iou;
    for (size_t i = 0; i < truth.size(); ++i) {
      if (used[i]) continue;
      const double iou = circle_iou(d, truth[i]);
      if (iou >= best_iou) {
        best_iou = iou;
        best = static_cast<int>(i);
      }
    }
    if (best < 0) {
      ++r.false_positives;
      continue;
    }
    used[best] = true;
    ++r.true_positives;
    r.centre_errors_px.push_back(std::hypot(d.x_px - truth[best].x_px, d.y_px - truth[best].y_px));
  }
  r.false_negatives = static_cast<int>(std::count(used.begin(), used.end(), false));
  return r;
}

DetectionScores detection_scores(int tp, int fp, int fn) {
  DetectionScores s;
  s.precision = tp + fp > 0 ? static_cast<double>(tp) / (tp + fp) : 1.0;
  s.recall = tp + fn > 0 ? static_cast<double>(tp) / (tp + fn) : 1.0;
  s.f1 =
      s.precision + s.recall > 0.0 ? 2.0 * s.precision * s.recall / (s.precision + s.recall) : 0.0;
  return s;
}

}  // namespace stereoball::ball_detector
