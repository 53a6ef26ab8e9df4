#pragma once
// A live stereo calibration session: per-frame board detections of both eyes in, poses taken
// only when the board stood still in both eyes, coverage of the image (x, y, size, skew) and
// of depth, and a verdict (RMS, rectified row error, baseline, eye order) before anything is
// written. Pure: no DDS, no clocks, no I/O; stamps are arguments.

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "stereo/core/board_calibration.hpp"
#include "stereo/core/board_coverage.hpp"
#include "stereo/core/still_board.hpp"

namespace stereoball::calibrate_live {

/// What a session needs and what its verdict demands.
struct LiveParams {
  stereo::BoardCalibrationParams board;  ///< board geometry and calibration options
  stereo::StillBoardParams still;        ///< when a board counts as still in both eyes
  int target_poses = 15;                 ///< poses to take before the verdict
  /// A still pose whose view parameters (x, y, size, skew) lie closer than this (sum of
  /// absolute differences) to a pose already taken adds nothing and is skipped.
  double min_pose_distance = 0.1;
  double max_rms_px = 0.5;        ///< verdict: largest stereo RMS reprojection error, px
  double max_row_error_px = 0.3;  ///< verdict: largest mean rectified row error, px
  double min_baseline_m = 0.0;    ///< verdict: smallest baseline, m (0 = not checked)
  double max_baseline_m = 0.0;    ///< verdict: largest baseline, m (0 = not checked)
  /// The board seen by one eye only for this long earns a hint to move it into both, ns.
  int64_t one_eye_hint_ns = 2'000'000'000;
  /// Success, or an error naming the field and its allowed range.
  Status validate() const;
};

/// A pose taken: its view parameters in the left image and its board disparity.
struct PoseRecord {
  int index = 0;                 ///< 1-based, in taking order
  stereo::BoardViewParams view;  ///< left-eye view parameters, each in [0, 1]
  double disparity_px = 0;       ///< mean left x minus right x of the corners, px
  int64_t left_stamp_ns = 0;     ///< capture stamp of the left corners
  int64_t right_stamp_ns = 0;    ///< capture stamp of the right corners
};

/// Where the session stands, for a live display.
struct Progress {
  int poses = 0;                     ///< poses taken
  int target_poses = 0;              ///< LiveParams::target_poses
  std::array<double, 4> coverage{};  ///< x, y, size, skew progress, each in [0, 1]
  double depth_coverage = 0;         ///< depth progress in [0, 1] (see depth_progress)
  stereo::EyeStillness left, right;  ///< how long each eye has seen the board still
  int frames = 0;                    ///< frames fed
  int frames_board_left = 0;         ///< frames whose left eye showed the board
  int frames_board_right = 0;        ///< frames whose right eye showed the board
  int skipped_duplicates = 0;        ///< still poses skipped as too close to a taken one
  std::string hint;                  ///< what the person holding the board should do
};

/// One pose's stereo reprojection error in the final calibration.
struct PoseError {
  std::string name;   ///< "pose N"
  double rms_px = 0;  ///< pixels
};

/// The outcome of finish(): the calibration and whether it may be written.
struct Verdict {
  bool pass = false;                      ///< every check passed: the file may be written
  std::vector<std::string> failures;      ///< one line per failed check, with the fix
  std::vector<std::string> warnings;      ///< works, but look at it (e.g. coverage short)
  stereo::BoardCalibrationResult result;  ///< the calibration and its figures
  std::vector<PoseError> per_pose;        ///< poses kept, with their errors
};

/// Depth progress of a set of board disparities: the nearest pose should show the board at
/// least twice the disparity of the farthest (twice as near); 1 - min/max over 0.5, capped.
double depth_progress(const std::vector<double>& disparities_px);

/// A live calibration of image_size images.
class LiveCalibration {
 public:
  /// params must be valid (validate()).
  LiveCalibration(const LiveParams& params, cv::Size image_size);

  /// One stereo frame: each eye's capture stamp and its board corners (empty = not found).
  /// Returns the pose when this frame completed a still interval in both eyes.
  std::optional<PoseRecord> add_frame(int64_t left_stamp_ns,
                                      const std::vector<cv::Point2f>& left_px,
                                      int64_t right_stamp_ns,
                                      const std::vector<cv::Point2f>& right_px);

  /// The state for a live display.
  Progress progress() const;

  /// True when the target number of poses is taken.
  bool enough_poses() const;

  /// Calibrates from the poses taken and judges the result; an error when it cannot
  /// calibrate at all (too few poses, OpenCV refuses), naming why.
  Result<Verdict> finish() const;

  /// The poses taken, as calibration input.
  const std::vector<stereo::PairCorners>& poses() const { return poses_; }

  /// The records of the poses taken.
  const std::vector<PoseRecord>& records() const { return records_; }

 private:
  bool too_close_to_taken(const stereo::BoardViewParams& view) const;
  std::string hint(const stereo::EyeStillness& left, const stereo::EyeStillness& right) const;
  std::string no_board_text() const;

  LiveParams params_;
  cv::Size image_size_;
  stereo::StillBoardSelector selector_;
  stereo::BoardCoverage coverage_;
  std::vector<stereo::PairCorners> poses_;
  std::vector<PoseRecord> records_;
  std::vector<double> disparities_px_;
  int frames_ = 0, frames_left_ = 0, frames_right_ = 0, duplicates_ = 0;
  int64_t one_eye_since_ns_ = -1;  // stamp since which only one eye sees the board
  int64_t first_stamp_ns_ = 0, last_stamp_ns_ = 0;
};

}  // namespace stereoball::calibrate_live
