#pragma once
// Accumulator helpers shared by the 2D voting detectors: ray plotting and peak extraction.

#include <opencv2/core.hpp>

#include <cstdint>
#include <span>
#include <vector>

namespace stereoball::ball_detector {

/// Adds one vote to each CV_16U accumulator cell on the ray start + t * dir, t in [t0, t1]
/// (dir need not be unit; t in pixels along it); clipped to the image; a full cell (65535) stays
/// full. Returns cells incremented. saturate = false: the caller knows no cell on the ray is full
/// (e.g. fewer than 65535 rays plotted into a zeroed map: a ray meets a cell once), and the
/// cells get plain increments, the same votes for less work.
std::int64_t plot_ray(cv::Mat& accumulator, double start_x, double start_y, double dir_x,
                      double dir_y, double t0_px, double t1_px, bool saturate = true);

/// What plot_ray derives from a ray's direction alone: a caller whose directions repeat (the
/// detector's small integer ones) computes it once per direction instead of once per ray.
struct RayDirection {
  double ux = 0.0, uy = 0.0;  ///< the direction made unit
  double abs_major = 0.0;     ///< |ux| or |uy|, whichever is larger (ux on ties)
  double slope = 0.0;         ///< minor coordinate per unit step of the major one
  std::int64_t dminor = 0;    ///< slope in 16.16 fixed point
  int step = 0;               ///< +1 or -1: the major coordinate's direction
  bool x_major = false;       ///< x is the major coordinate
  bool plottable = false;     ///< false for a zero (or NaN-free non-positive) norm: no cell
};

/// The direction part of plot_ray(dir_x, dir_y), the same operations.
RayDirection ray_direction(double dir_x, double dir_y);

/// plot_ray with its direction part computed already: the same cells as plot_ray(dir_x,
/// dir_y) for dir = ray_direction(dir_x, dir_y).
std::int64_t plot_ray(cv::Mat& accumulator, double start_x, double start_y, const RayDirection& dir,
                      double t0_px, double t1_px, bool saturate = true);

/// Largest of row[0, w), or 0 if all are below (vote maps hold no negative value).
int row_maximum(const int* row, int w);

/// A local maximum of a smoothed accumulator.
struct Peak {
  int x = 0;
  int y = 0;
  float value = 0.0f;  ///< smoothed votes (or normalised support for the 3D CHT)
};

/// Local maxima (3x3) of a CV_32S or CV_32F map with value >= min_value, strongest first, no
/// two closer than min_separation_px, at most max_peaks.
std::vector<Peak> find_peaks(const cv::Mat& smoothed, float min_value, double min_separation_px,
                             int max_peaks);
/// Same for a CV_32S map whose rows' largest values are known (box_filter's row_maxima, one per
/// row): rows below min_value are skipped without a scan.
std::vector<Peak> find_peaks(const cv::Mat& smoothed, float min_value, double min_separation_px,
                             int max_peaks, std::span<const int> row_maxima);

/// Maximum / mean of a map (0 for an all-zero map): how sharp the strongest peak is.
double peak_to_mean(const cv::Mat& smoothed);

}  // namespace stereoball::ball_detector
