#pragma once
// Coarse-to-fine search of large frames: the image is searched on a reduced pyramid level (each
// pixel the mean of a 2^level block, so a k window sees the same scene as at the reference
// width), and each circle found there is refined on the full-resolution edges (the edge step
// at full width costs a fraction of the voting, whose lines there are 2^level times longer and
// whose windows 2^level times wider). Radii too small for the reduced image are left to a
// full-resolution search (the fine path).

#include "ball_detector/core/circle.hpp"
#include "ball_detector/core/edge_map.hpp"
#include "ball_detector/core/p2p_detector.hpp"

#include <opencv2/core.hpp>

#include <span>
#include <vector>

namespace stereoball::ball_detector {

/// Settings of the coarse-to-fine search.
struct CoarseToFineParams {
  /// The reduced image is about this wide: level = round(log2(width / this)), pixels; 0 = off
  /// (every image at full resolution; 640 = the detector's reference width).
  int target_width_px = 0;
  /// Smallest radius searched on the reduced image, its pixels: smaller radii of the range are
  /// searched at full resolution (the fine path), > 0.
  double min_coarse_radius_px = 3.5;
  /// Deepest level used, [0, 4].
  int max_level = 3;
  /// A reduced image's circle whose full-resolution refinement moves its centre or changes its
  /// radius by more than this many radii is dropped (it found another outline), [0, 1]; 0 = off.
  double max_refine_shift = 0.15;

  /// Success, or an error naming the first bad field and its allowed range.
  Status validate() const;
};

/// The pyramid level an image this wide is searched on (0 = full resolution).
int coarse_level(int image_width_px, const CoarseToFineParams& params);

/// A search's radius range split between the levels: coarse in the reduced image's pixels
/// (empty when min_px > max_px), fine in full-resolution pixels (empty likewise).
struct RadiusSplit {
  RadiusRange coarse_px{1.0, 0.0};
  RadiusRange fine_px{1.0, 0.0};
};

/// Whether a range holds any radius.
inline bool holds_radii(const RadiusRange& r) {
  return r.min_px <= r.max_px;
}

/// full (full-resolution pixels) split at level: radii of at least min_coarse_radius_px on the
/// reduced image go to it, smaller ones to the fine path (all of it at level 0).
RadiusSplit split_radius_range(const RadiusRange& full, int level, double min_coarse_radius_px);

/// Pixel-to-Pixel settings for the reduced image of a level: lengths divided by 2^level, each k
/// divided and rounded up (same scene window), peak votes by 2^level, no perspective camera
/// (the full-resolution refinement scores the outline), no polish; at least max_peaks_examined
/// circles kept (the full resolution keeps the best max_circles).
PixelToPixelParams params_at_level(const PixelToPixelParams& full, int level);

/// image reduced by 2^level into out (each pixel the mean of its block; the last odd row or
/// column is dropped); level 0 copies nothing: out is image.
void reduce_image(const cv::Mat& image, int level, cv::Mat& out);

/// even (CV_8U, even width and height) halved into half: each pixel the rounded mean of a 2 x 2
/// block, (a + b + c + d + 2) >> 2, the same bits as cv::resize(even, half, even.size() / 2, 0,
/// 0, cv::INTER_AREA), which it is where no faster path applies.
void halve_image(const cv::Mat& even, cv::Mat& half);

/// A reduced image's circle in full-resolution pixels (score kept).
Circle to_full_resolution(const Circle& reduced, int level);

/// Circles of the reduced image (level's pixels) refined on fine's full-resolution edges
/// (find_edges, cast_votes or a detect of the full image): each mapped to full resolution and
/// refined as fine's refine_seeds does (robust fit, polish, min_score, its radius range and
/// border rule); best first, separated, at most fine's max_circles.
/// With max_shift > 0, a circle whose refinement moved its centre, or changed its radius, by
/// more than max_shift times the seed's radius is dropped: it found another outline than the
/// one the reduced image voted for.
std::vector<Circle> refine_coarse_circles(const PixelToPixelDetector& fine,
                                          std::span<const Circle> reduced, int level,
                                          double max_shift = 0.0);

/// Whether refined (full resolution) stays within max_shift seed radii of seed in centre and
/// radius; always true for max_shift <= 0.
bool holds_seed(const Circle& refined, const Circle& seed, double max_shift);

}  // namespace stereoball::ball_detector
