#pragma once
// Decides which stereo/calibration the detector uses. A calibration replaces the one in use
// only when it fits the frames: one of another image size than the frames arriving is held
// back (the good one stays), and is taken once frames of its size keep arriving (a camera
// restarted at a new resolution). Pure logic: sizes in, decisions out.

#include <opencv2/core.hpp>

#include <optional>
#include <string>

namespace stereoball::ball_detector {

/// What to do with a calibration that just arrived.
struct CalibrationDecision {
  bool use = false;    ///< build the pipeline from it now
  std::string reason;  ///< why it was held back (use == false)
};

class CalibrationGate {
 public:
  /// Consecutive frames of a held-back calibration's size after which it is used.
  static constexpr int kFramesToSwitch = 3;

  /// A calibration of image size `size` arrived (already validated and within the limits).
  CalibrationDecision offer(cv::Size size);
  /// The offered calibration was applied (use == true, or a switch).
  void applied(cv::Size size);
  /// A frame of (declared) size arrived; true when the held-back calibration should now be
  /// used because kFramesToSwitch frames in a row had its size.
  bool frame(cv::Size size);
  /// Size of the held-back calibration, if any.
  std::optional<cv::Size> pending() const { return pending_; }

 private:
  std::optional<cv::Size> in_use_;
  std::optional<cv::Size> last_frame_;
  std::optional<cv::Size> pending_;
  int pending_frames_ = 0;
};

}  // namespace stereoball::ball_detector
