#pragma once
// Scoring detections against ground truth: circle IoU, greedy matching, precision/recall/F1.

#include "ball_detector/core/circle.hpp"

#include <vector>

namespace stereoball::ball_detector {

/// Intersection over union of two discs, in [0, 1].
double circle_iou(const Circle& a, const Circle& b);

/// Outcome of matching one image's detections to its ground truth.
struct MatchResult {
  int true_positives = 0;
  int false_positives = 0;
  int false_negatives = 0;
  std::vector<double> centre_errors_px;  ///< one per true positive, pixels
};

/// Greedy one-to-one matching, detections in decreasing score, pairs with IoU >= min_iou.
MatchResult match_circles(const std::vector<Circle>& detections, const std::vector<Circle>& truth,
                          double min_iou);

/// Precision, recall and F1 from summed counts (1 when nothing was expected nor found).
struct DetectionScores {
  double precision = 0.0;
  double recall = 0.0;
  double f1 = 0.0;
};

/// Scores from totals of true positives, false positives and false negatives.
DetectionScores detection_scores(int tp, int fp, int fn);

}  // namespace stereoball::ball_detector
