#pragma once
// Runs the ball detector's stereo pipeline (the node's per-frame functions) over real
// backgrounds with composited balls and over the same backgrounds without a ball.

#include "ball_detector/pipeline/detector_params.hpp"
#include "composite_scenes.hpp"

#include <string>
#include <vector>

namespace stereoball::composite {

/// What the pipeline made of one composited ball.
struct BallOutcome {
  std::string background;
  Ball ball;
  bool found = false;
  std::string status;         ///< pipeline status name, with its reason when not found
  double error_m = 0;         ///< |found centre - true centre|, metres (found only)
  double error_of_depth = 0;  ///< error_m / true depth
  double ms = 0;              ///< pipeline time for the frame, ms
};

/// Figures of one suite run.
struct SuiteResult {
  std::vector<BallOutcome> balls;
  int frames_without_ball = 0;
  int false_detections = 0;                ///< FOUND on a background without a ball
  std::vector<std::string> false_details;  ///< background: where
  double found_fraction() const;
  double median_error_of_depth() const;  ///< over found balls
  double median_ms() const;              ///< over every frame with a ball
};

/// Suite settings: per background balls_per_background balls of radius_m at depths in
/// [min_depth_m, max_depth_m] (place_balls, seed + background index).
struct SuiteOptions {
  int balls_per_background = 5;
  double radius_m = 0.11;
  double min_depth_m = 0.8;
  double max_depth_m = 3.0;
  unsigned seed = 17;
};

/// The detector settings for floating composited balls: params with the ball's diameter and
/// no floor check (a composited ball does not rest on a floor).
ball_detector::BallDetectorParams composite_params(ball_detector::BallDetectorParams params,
                                                   double radius_m);

/// Runs the pipeline on every background with each of its balls, and once without.
SuiteResult run_suite(const std::vector<Background>& backgrounds,
                      const ball_detector::BallDetectorParams& params, const SuiteOptions& options);

}  // namespace stereoball::composite
