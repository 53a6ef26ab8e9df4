#pragma once
// "The board stood still in both eyes": picks calibration poses from a stream of per-eye
// chessboard detections of free-running (unsynchronised) cameras. Pure: stamps are arguments.

#include "common/util/result.hpp"
#include "stereo/core/rectifier.hpp"

#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace stereoball::stereo {

/// When a board counts as still.
struct StillBoardParams {
  /// Largest distance any corner may move from where it was when the eye's still run began,
  /// pixels; more starts a new run.
  double max_motion_px = 0.5;
  /// How long both eyes' still runs must overlap (each on its own capture stamps), ns.
  int64_t still_ns = 300'000'000;
  /// A longer gap between two detections of one eye ends its run (a stalled camera), ns.
  int64_t max_gap_ns = 250'000'000;
  /// Success, or an error naming the field and its allowed range.
  Status validate() const;
};

/// A pose taken: the latest corners of each eye, both inside the common still interval.
struct StillPose {
  std::vector<cv::Point2f> left_px;   ///< left corners, board order
  std::vector<cv::Point2f> right_px;  ///< right corners, as detected (align the order yourself)
  int64_t left_stamp_ns = 0;          ///< capture stamp of the left corners
  int64_t right_stamp_ns = 0;         ///< capture stamp of the right corners
  int64_t still_from_ns = 0;          ///< start of the interval in which both eyes were still
};

/// How long one eye has seen the board still (for a live display).
struct EyeStillness {
  bool board_seen = false;  ///< the eye's latest detection found the board
  int64_t still_ns = 0;     ///< length of its current still run, ns (0 when not seen)
};

/// Feeds per-eye detections in each eye's capture order; returns a pose once the board has
/// moved less than max_motion_px in both eyes for still_ns of common time, then not again
/// until the board has moved (or was lost) in both eyes.
class StillBoardSelector {
 public:
  /// params must be valid (validate()).
  explicit StillBoardSelector(const StillBoardParams& params);

  /// One detection of one eye at its capture stamp; empty corners = board not found. A stamp
  /// older than the eye's previous one restarts that eye's run. Returns the pose when taken.
  std::optional<StillPose> add(Eye eye, int64_t stamp_ns, const std::vector<cv::Point2f>& corners);

  /// The current state of one eye.
  EyeStillness stillness(Eye eye) const;

  /// Forgets both eyes' runs (e.g. the cameras were restarted).
  void reset();

 private:
  struct Run {
    bool active = false;
    bool taken = false;  // a pose was taken from this run
    int64_t start_ns = 0, last_ns = 0;
    std::vector<cv::Point2f> anchor, last;
  };

  StillBoardParams params_;
  Run runs_[2];
};

/// Largest distance between corresponding points, pixels; infinity if the sizes differ.
double max_corner_motion_px(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b);

}  // namespace stereoball::stereo
