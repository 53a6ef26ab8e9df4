#pragma once
// How much of the calibration space a set of board views covers, measured as ROS
// camera_calibration does: where the board sits in the image (X, Y), how large it looks
// (size) and how much it is tilted (skew), each in [0, 1].

#include <opencv2/core.hpp>

#include <array>
#include <optional>
#include <vector>

namespace stereoball::stereo {

/// One board view's position in the calibration space, each in [0, 1].
struct BoardViewParams {
  double x = 0;     ///< horizontal position of the board within the room the image leaves it
  double y = 0;     ///< vertical position, likewise
  double size = 0;  ///< sqrt(board area / image area), board = quad of the outer inner corners
  double skew = 0;  ///< 2 |90 deg - angle at the top-right corner|, radians, capped at 1
};

/// The view parameters of inner corners (findChessboardCorners order) of a board with
/// inner_corners (cols x rows) in an image_size image; nullopt if the count does not match.
std::optional<BoardViewParams> board_view_params(const std::vector<cv::Point2f>& corners_px,
                                                 cv::Size inner_corners, cv::Size image_size);

/// Spread of the views taken so far per parameter, and the progress toward ROS's goals.
class BoardCoverage {
 public:
  /// Spread needed for full coverage of x, y, size, skew (ROS camera_calibration's).
  static constexpr std::array<double, 4> kGoal{0.7, 0.7, 0.4, 0.5};

  /// Adds one view.
  void add(const BoardViewParams& view);
  /// Progress of x, y, size, skew in [0, 1]: (max - min) / goal, capped; 0 before any view.
  std::array<double, 4> progress() const;
  /// True when every parameter has reached its goal.
  bool complete() const;
  /// Number of views added.
  int views() const { return views_; }

 private:
  std::array<double, 4> lo_{}, hi_{};
  int views_ = 0;
};

}  // namespace stereoball::stereo
