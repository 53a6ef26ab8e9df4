#include "ball_detector/pipeline/calibration_gate.hpp"

namespace stereoball::ball_detector {
namespace {

std::string dims(cv::Size s) {
  return std::to_string(s.width) + "x" + std::to_string(s.height);
}

}  // namespace

CalibrationDecision CalibrationGate::offer(cv::Size size) {
  // Nothing to protect yet, or no frame to compare with: the calibration is the best guess.
  if (!in_use_ || !last_frame_ || size == *last_frame_) {
    pending_.reset();
    return {true, ""};
  }
  pending_ = size;
  pending_frames_ = 0;
  return {false, "it is for " + dims(size) + " images but the frames are " + dims(*last_frame_) +
                     "; keeping the " + dims(*in_use_) + " calibration until " +
                     std::to_string(kFramesToSwitch) + " frames of " + dims(size) + " arrive"};
}

void CalibrationGate::applied(cv::Size size) {
  in_use_ = size;
  pending_.reset();
  pending_frames_ = 0;
}

bool CalibrationGate::frame(cv::Size size) {
  last_frame_ = size;
  if (!pending_) return false;
  pending_frames_ = size == *pending_ ? pending_frames_ + 1 : 0;
  return pending_frames_ >= kFramesToSwitch;
}

}  // namespace stereoball::ball_detector
