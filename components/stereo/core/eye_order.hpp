#pragma once
// Are the two images of a frame in the calibration's order? Cameras plugged into the other
// USB ports (or the devices named the other way round) swap the eyes: the calibration then
// rectifies each image with the other camera's model and every disparity comes out negative.
// The images say so: features of a correctly ordered pair match on the same rectified row at a
// positive disparity, those of a swapped pair only once the eyes are exchanged.

#include "stereo/core/rectifier.hpp"
#include "stereo/core/row_check.hpp"

#include <opencv2/core.hpp>

#include <cstddef>
#include <optional>
#include <string>

namespace stereoball::stereo {

/// Matches on the same rectified row with the images as given and exchanged.
struct EyeOrderEvidence {
  std::size_t matches_as_given = 0;  ///< features matched within max_row_diff_px, as given
  std::size_t matches_swapped = 0;   ///< the same with left and right exchanged
  bool swapped = false;              ///< the exchanged order is clearly the better one
};

/// Thresholds of the eye-order check.
struct EyeOrderParams {
  /// Feature matching (row_check.hpp); 100 features decide as clearly as 400, 4x sooner.
  RowCheckParams rows{.max_features = 100};
  double max_row_diff_px = 2.0;  ///< a match counts on rows this close, pixels
  std::size_t min_matches = 20;  ///< fewer matches either way: no verdict (a blank scene)
  double min_ratio = 3.0;        ///< swapped when it matches this many times more features
};

/// Compares the two orders on one frame (raw images unless rectified; grey or BGR, the
/// calibration's size). Costs two rectifications and two feature matchings (tens of ms): a
/// start-up check, not a per-frame one.
EyeOrderEvidence check_eye_order(const Rectifier& rectifier, const cv::Mat& left,
                                 const cv::Mat& right, bool rectified,
                                 const EyeOrderParams& params = {});

/// One line for logs when evidence.swapped, nullopt otherwise; how_to_fix is appended.
std::optional<std::string> describe_swapped_eyes(const EyeOrderEvidence& evidence,
                                                 const std::string& how_to_fix);

/// Checks the eye order on a few frames of a stream until one decides (a blank or dark scene
/// does not): the first frame, then every frames_between-th, at most max_checks times.
class EyeOrderWatch {
 public:
  explicit EyeOrderWatch(int max_checks = 5, int frames_between = 100,
                         const EyeOrderParams& params = {});
  /// Whether the next frame will be checked: a caller that must convert a frame first (yuyv)
  /// converts only those.
  bool due() const;
  /// Counts a frame; checks it when due and returns the evidence of that check.
  std::optional<EyeOrderEvidence> step(const Rectifier& rectifier, const cv::Mat& left,
                                       const cv::Mat& right, bool rectified);
  /// Counts a frame whose images could not be had (instead of step): when it was due, it uses
  /// up a check, so a camera whose frames never convert ends the watch after max_checks.
  void skip();
  /// No check left and no decision: the order stays unknown until reset().
  bool given_up() const;
  /// Starts over (e.g. a new calibration).
  void reset();

 private:
  int max_checks_;
  int frames_between_;
  EyeOrderParams params_;
  int frames_ = 0;
  int checks_ = 0;
  bool decided_ = false;
};

}  // namespace stereoball::stereo
