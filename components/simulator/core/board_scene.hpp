#pragma once
// The calibration scene: a chessboard carried through poses in front of the rig (held still,
// then moved to the next pose), rendered in both eyes through the true rig, lens distortion
// included, with optionally free-running eyes (the right eye captures eye_skew_s later).

#include <cstdint>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "common/util/result.hpp"
#include "simulator/core/rig.hpp"
#include "simulator/core/vec3.hpp"

namespace stereoball::simulator {

/// A printed chessboard.
struct CalibrationBoard {
  int cols = 9;             ///< inner corners per row
  int rows = 6;             ///< inner corners per column
  double square_m = 0.03;   ///< square side, metres
  double margin_m = 0.03;   ///< white border around the squares, metres
  double black_dn = 30.0;   ///< dark squares, 0..255
  double white_dn = 220.0;  ///< light squares and border, 0..255
};

/// Where the board is: its inner-corner grid's centre and orientation in the left camera's
/// frame (x right, y down, z forward). All angles 0 = facing the camera, rows horizontal.
struct BoardPose {
  Vec3d centre_m{0.0, 0.0, 0.6};  ///< grid centre, left camera frame, metres
  double tilt_x_rad = 0.0;        ///< right-handed about the board's row axis (> 0: bottom away)
  double tilt_y_rad = 0.0;        ///< right-handed about its column axis (> 0: left side away)
  double roll_rad = 0.0;  ///< right-handed about the viewing axis (> 0: clockwise in the image)
};

/// One pose of the board: held still for hold_s, then moved to the next pose in move_s.
struct BoardHold {
  BoardPose pose;
  double hold_s = 1.0;  ///< seconds still
  double move_s = 1.0;  ///< seconds to the next pose (ignored after the last)
};

/// Ranges of the pose generator (CalibrationScene from a seed).
struct BoardPoseRanges {
  int count = 20;             ///< poses to draw
  double near_m = 0.45;       ///< nearest grid centre depth, metres
  double far_m = 1.5;         ///< farthest, metres
  double max_tilt_rad = 0.7;  ///< largest tilt about either board axis
  double max_roll_rad = 0.3;  ///< largest roll
  double hold_s = 1.0;        ///< hold time of every pose
  double move_s = 1.0;        ///< time between poses
  uint64_t seed = 1;          ///< which pose set
  /// Success, or the first invalid field with its allowed range.
  Status validate() const;
};

/// A calibration scene (Scenario::calibration).
struct CalibrationScene {
  CalibrationBoard board;
  std::vector<BoardHold> holds;  ///< in order; the board starts at the first
  /// Poses drawn by draw_board_holds (when the rig is known: with_drawn_holds) instead of holds.
  std::optional<BoardPoseRanges> random_poses;
  double eye_skew_s = 0.0;       ///< right eye captures this much after the left (< 0: before)
  double background_dn = 115.0;  ///< plain background behind the board, 0..255
  /// Success, or the first invalid field with its allowed range.
  Status validate() const;
  /// Seconds from the first hold to the end of the last (of the drawn ones, if random).
  double duration_s() const;
};

/// The scene with random_poses drawn for rig into holds (unchanged if it has no random_poses).
CalibrationScene with_drawn_holds(const CalibrationScene& scene, const StereoRig& rig);

/// The board's pose at t_s (smooth moves, still during holds; clamped to the scene's span).
BoardPose board_pose_at(const CalibrationScene& scene, double t_s);

/// Index of the hold in force at t_s, or -1 while the board moves.
int hold_index_at(const CalibrationScene& scene, double t_s);

/// The board's inner corners (row by row, left to right in board coordinates) in the frame
/// of the left camera, metres.
std::vector<Vec3d> board_corners_cam(const CalibrationBoard& board, const BoardPose& pose);

/// A point of the left camera frame in eye's camera frame.
Vec3d left_cam_to_eye(const StereoRig& rig, Eye eye, const Vec3d& p_left);

/// True raw (distorted) pixels of the inner corners in one eye.
std::vector<cv::Point2d> board_corners_px(const StereoRig& rig, Eye eye,
                                          const CalibrationBoard& board, const BoardPose& pose);

/// True if the whole board (border included) is in front of both eyes and inside both images
/// with margin_px to spare.
bool board_in_view(const StereoRig& rig, const CalibrationBoard& board, const BoardPose& pose,
                   double margin_px);

/// Draws ranges.count board poses that cover the image (x, y over a 3x3 grid), the size (depth
/// bands near to far) and the skew (tilts about both axes and the diagonals) the way ROS
/// camera_calibration measures coverage, each fully in view of both eyes. Depends only on
/// (rig, board, ranges, seed); SplitMix64, the same on every platform.
std::vector<BoardHold> draw_board_holds(const StereoRig& rig, const CalibrationBoard& board,
                                        const BoardPoseRanges& ranges, uint64_t seed);

/// Renders the board scene through the rig's true cameras (exact inverse distortion per pixel,
/// edges box-filtered analytically so corners are exact to a small fraction of a pixel).
class BoardRenderer {
 public:
  /// Precomputes each eye's undistorted rays (~0.3 M Newton inversions per eye).
  BoardRenderer(const StereoRig& rig, const CalibrationScene& scene);
  /// Renders eye with the board at pose into out (CV_8UC3 BGR, grey).
  void render(Eye eye, const BoardPose& pose, cv::Mat& out) const;

 private:
  Intrinsics k_[2];
  Mat3 r_right_from_left_;
  Vec3d t_right_from_left_;
  int width_, height_;
  CalibrationBoard board_;
  double background_dn_;
  std::vector<cv::Point2d> rays_[2];  // normalised undistorted (x, y) per raw pixel
};

}  // namespace stereoball::simulator
