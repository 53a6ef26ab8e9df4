#pragma once
// The simulated stereo rig: camera poses on the robot and the true calibration.

#include "simulator/core/camera_model.hpp"
#include "simulator/core/sim_params.hpp"
#include "simulator/core/vec3.hpp"
#include "stereo/core/calibration.hpp"

namespace stereoball::simulator {

/// Which camera.
enum class Eye { kLeft = 0, kRight = 1 };

/// Pose of a camera in the robot frame (x forward, y left, z up); camera frame is OpenCV's.
struct CameraPose {
  Mat3 r_robot_from_cam;  ///< columns: camera x (right), y (down), z (forward) in robot axes
  Vec3d position_m;       ///< optical centre in the robot frame, metres
};

/// Both cameras of the rig (true, including the right camera's mounting error).
class StereoRig {
 public:
  /// Builds the rig; params must be valid (SimParams::validate()).
  explicit StereoRig(const SimParams& params);

  /// Intrinsics of one eye.
  const Intrinsics& intrinsics(Eye eye) const { return k_[static_cast<int>(eye)]; }
  /// Pose of one eye on the robot.
  const CameraPose& pose(Eye eye) const { return pose_[static_cast<int>(eye)]; }
  /// The exact calibration of this rig, rectified with cv::stereoRectify.
  const stereo::StereoCalibration& calibration() const { return calib_; }
  /// Image width, pixels.
  int width_px() const { return width_; }
  /// Image height, pixels.
  int height_px() const { return height_; }

 private:
  int width_;
  int height_;
  Intrinsics k_[2];
  CameraPose pose_[2];
  stereo::StereoCalibration calib_;
};

}  // namespace stereoball::simulator
