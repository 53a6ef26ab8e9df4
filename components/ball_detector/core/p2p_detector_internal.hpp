#pragma once
// What the Pixel-to-Pixel detector's files share (p2p_detector.cpp and the p2p_*.cpp files
// beside it): the largest k, the accumulator's memory and the robust refinement settings.
// Not part of the detector's API.

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/circle_fit.hpp"
#include "ball_detector/core/p2p_detector.hpp"

#include <opencv2/core.hpp>

#include <vector>

namespace stereoball::ball_detector::p2p_detail {

constexpr int kMaxK = 31;  // window rows are read as one 63-bit slice

/// Makes view a rows x cols map of type in store's memory, growing store when it is too small.
void map_in_store(cv::Mat& store, cv::Mat& view, int rows, int cols, int type);

/// The refinement options of PixelToPixelParams::polish (and rescue_weak_from).
inline RefineParams polish_refine_params(RefineParams refine) {
  refine.first_band_px = PixelToPixelParams::kPolishFirstBandPx;
  refine.robust_fit_floor_px = PixelToPixelParams::kPolishRobustFloorPx;
  return refine;
}

/// The best circles first, none within min_separation_px of a better one, at most max_circles.
std::vector<Circle> best_separated(std::vector<Circle> found, double min_separation_px,
                                   int max_circles);

}  // namespace stereoball::ball_detector::p2p_detail
