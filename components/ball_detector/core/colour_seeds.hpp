#pragma once
// Seeds for the circle refinement from colour, not from votes: regions whose chroma stands out
// from the image's own, about as wide as tall and as large as a ball may be. A two-tone ball
// whose light half matches the floor has only part of its outline, and the edges of its stripes
// inside, so the accumulator ranks its centre below thousands of chance peaks; its coloured half
// still stands out as a region. A ball whose chroma the floor shares (blue stripes on brown
// planks) stands out by its colour instead: a colour the image has little of. The seeds are
// refined and scored on the edges as any candidate is: colour only says where to look.

#include <opencv2/core.hpp>

#include <vector>

#include "ball_detector/core/circle.hpp"

namespace stereoball::ball_detector {

struct ColourSeedParams {
  bool enabled = true;         ///< (for callers: whether to look for seeds at all)
  int max_seeds = 4;           ///< the largest regions kept
  double min_chroma = 40.0;    ///< chroma (max - min of B, G, R) a region must exceed at least
  double spread_factor = 6.0;  ///< ... and the image's median plus this many robust sigmas
  /// ... or have a colour (8 levels per channel) covering less than this fraction of the image
  /// and a chroma at least the image's median (0 = off)
  double rare_fraction = 0.01;
  double min_fill = 0.35;   ///< region area / bounding box area (a disc: 0.785)
  double max_aspect = 2.0;  ///< longer / shorter side of the bounding box
  /// (for callers) a seed whose outline the frame's edges miss, and a track's expected outline,
  /// are searched again on the image with its brightness removed (remove_brightness in
  /// edge_map.hpp), in both eyes
  bool chroma_outlines = true;
};

/// Chroma per pixel of a BGR image: max - min of B, G and R (CV_8UC1, same size).
cv::Mat colour_chroma(const cv::Mat& bgr);

/// Circles around the regions of outstanding chroma in a BGR image (searched at half
/// resolution), with radii in [min_radius_px, max_radius_px], largest region first; empty for a
/// grey or empty image.
std::vector<Circle> colour_blob_seeds(const cv::Mat& bgr, double min_radius_px,
                                      double max_radius_px, const ColourSeedParams& params = {});

}  // namespace stereoball::ball_detector
