#pragma once
// Public interface shared by every circle detector (Pixel-to-Pixel and the baselines).

#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::ball_detector {

/// One detected circle in image pixels (pixel centres at integer coordinates).
struct Circle {
  double x_px = 0.0;       ///< centre column, pixels
  double y_px = 0.0;       ///< centre row, pixels
  double radius_px = 0.0;  ///< radius, pixels
  double score = 0.0;      ///< confidence in [0, 1]; below the detector's threshold = "no circle"
  /// The same circle to the bit: place, radius and score.
  friend bool operator==(const Circle&, const Circle&) = default;
};

/// What a voting detector saw on its last image, for --debug-dir and the bench.
struct DetectionDiagnostics {
  cv::Mat edges;                ///< binary edge map actually used, CV_8U 0/255
  cv::Mat accumulator;          ///< smoothed 2D vote map, CV_32S box sums (empty for CHT / OpenCV)
  std::int64_t voters = 0;      ///< edge points that cast a vote (one line or circle each)
  std::int64_t increments = 0;  ///< accumulator cells incremented in total
  double peak_to_mean = 0.0;    ///< smoothed accumulator maximum / its mean (peak sharpness)
};

/// A circle detector: grey or BGR image in, candidates sorted by decreasing score out.
class CircleDetector {
 public:
  virtual ~CircleDetector() = default;
  /// Detects circles in a CV_8UC1 or CV_8UC3 image; invalid images give an empty result.
  virtual std::vector<Circle> detect(const cv::Mat& bgr_or_grey) = 0;
  /// Diagnostics of the last detect() call, or nullptr if the method has none.
  virtual const DetectionDiagnostics* diagnostics() const { return nullptr; }
  /// Short method name ("p2p", "cht", "gradient", "opencv", "opencv-alt").
  virtual std::string name() const = 0;
};

/// Success, or why an image cannot be processed (empty, wrong depth or channel count).
Status validate_image(const cv::Mat& image);

/// Settings common to every method, used by the factory (the CLI maps its flags onto these).
struct DetectorOptions {
  std::vector<int> k_values = {5};  ///< Pixel-to-Pixel half window sizes (p2p only)
  int max_circles = 5;              ///< most candidates returned
  double min_radius_px = 4.0;       ///< smallest radius searched, pixels
  double max_radius_px = 120.0;     ///< largest radius searched, pixels
  double min_separation_px = 10.0;  ///< closest two returned centres may be, pixels
  double min_score = 0.55;          ///< candidates below this score are dropped, [0, 1]
  double opencv_param2 = -1.0;      ///< OpenCV param2 override (<0: method default)
  bool coarse_to_fine = false;      ///< p2p: PixelToPixelParams::coarse_to_fine (single images)
};

/// Method names the factory knows, in display order.
std::vector<std::string> detector_names();

/// Builds a detector by method name, or nullopt-like nullptr plus a message for a bad name/option.
std::unique_ptr<CircleDetector> make_detector(const std::string& method,
                                              const DetectorOptions& options, std::string* error);

}  // namespace stereoball::ball_detector
