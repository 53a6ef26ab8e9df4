#pragma once
// The whole-frame and radius-band searches of a wide frame, coarse to fine
// (core/coarse_to_fine.hpp): the left eye votes reduced to about coarse_to_fine.target_width_px,
// each circle found there is refined on the full-resolution edges, and radii too small for the
// reduced eye are voted for at full width (README: coarse to fine).

#include <opencv2/core.hpp>

#include <atomic>
#include <optional>
#include <vector>

#include "ball_detector/core/coarse_to_fine.hpp"
#include "ball_detector/core/p2p_detector.hpp"
#include "ball_detector/pipeline/detector_params.hpp"
#include "stereo/core/sphere_outline.hpp"

namespace stereoball::ball_detector {

struct SearchTools;

/// The reduced left eye's equipment for one calibration (SearchTools::coarse).
struct CoarseSearch {
  int level = 0;              ///< pyramid level of the left eye's votes (0 = full width: off)
  RadiusSplit split;          ///< the radius range between the reduced eye and full width
  PixelToPixelParams params;  ///< the reduced eye's detector settings (its pixels)
  std::optional<PixelToPixelDetector> detector;      ///< votes on the reduced left eye
  std::vector<PixelToPixelDetector> band_detectors;  ///< its radius bands
  std::optional<PixelToPixelDetector> fine_path;     ///< radii below the reduced eye's, full width
  cv::Mat reduced_left;                              ///< the reduced rectified left eye

  /// Sets the level and detectors for frames image_width_px wide with the pipeline's (scaled)
  /// params; off when the frame is not wider than the target or no radius suits the reduced eye.
  void set_up(const BallDetectorParams& params, int image_width_px,
              const std::optional<stereo::PinholeCamera>& left_camera);
  /// Whether the whole-frame and band searches run coarse to fine.
  bool on() const { return level > 0; }
};

/// The whole rectified left eye's votes (tools.rect_left): on it reduced when coarse to fine (the
/// left detector then holds the full-resolution edges only), else as the full search; false for
/// an invalid image.
bool cast_left_votes(SearchTools& tools);

/// The whole-range circles of the reduced eye's votes refined at full width, with the fine
/// path's, best first, at most max_candidates_per_eye.
std::vector<Circle> coarse_left_circles(SearchTools& tools);

/// The circles of the reduced eye (its pixels) refined on the left detector's full-resolution
/// edges, the best `keep` of them at most.
std::vector<Circle> refined_at_full_width(const SearchTools& tools,
                                          const std::vector<Circle>& reduced, std::size_t keep);

}  // namespace stereoball::ball_detector
