#pragma once
// The live calibration of a running rig as both front ends use it (the terminal tool and the
// browser page of `stereoball view --calibrate`): decoded raw stereo frames in, board corners
// found in each eye, a LiveCalibration fed, frames that cannot be used refused with the
// reason, a stall of the cameras noticed, the verdict computed once enough poses are taken
// and the whole state as JSON for the page. Pure: time is an argument, nothing is written
// here (live_output.hpp writes the file).

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "live_calibration.hpp"

namespace stereoball::calibrate_live {

/// Board corners in one eye (grey or BGR): searched on a copy at most 800 px wide (fast on
/// large sensors), refined to sub-pixel on the full image; empty when the whole board is not
/// seen.
std::vector<cv::Point2f> find_live_corners(const cv::Mat& eye,
                                           const stereo::BoardCalibrationParams& params);

/// One line per figure of a verdict, as the terminal prints them and the log keeps them.
std::vector<std::string> verdict_lines(const Verdict& verdict);

/// A station's settings.
struct StationParams {
  LiveParams live;                   ///< the calibration session
  int64_t stall_ns = 2'000'000'000;  ///< no frame for this long: the cameras stopped, ns
};

/// One raw stereo frame, decoded.
struct StationFrame {
  cv::Mat left, right;         ///< the eyes, grey or BGR, same size
  int64_t left_stamp_ns = 0;   ///< left capture stamp
  int64_t right_stamp_ns = 0;  ///< right capture stamp
  uint64_t seq = 0;            ///< frame sequence number
  bool rectified = false;      ///< the publisher rectified the eyes (calibration needs raw)
  std::string source;          ///< where the frames come from (for the page)
};

/// What one frame changed.
struct StationStep {
  std::optional<PoseRecord> pose;  ///< the pose this frame completed
  std::string refused;             ///< why the frame was not used (empty when used)
  bool verdict_ready = false;      ///< this frame completed the poses: the verdict is in
};

/// The session with its failures and verdict; one thread at a time.
class LiveStation {
 public:
  /// params.live must be valid (LiveParams::validate()).
  explicit LiveStation(const StationParams& params);

  /// One decoded frame at monotonic time now_ns: corners searched in both eyes, the session
  /// fed. A rectified frame or a frame of another size than the first stops the session with
  /// the reason (fatal()); once the verdict is in, frames only update the drawn corners.
  StationStep add_frame(const StationFrame& frame, int64_t now_ns);
  /// As add_frame with the corners already found (tests, replays).
  StationStep add_corners(const StationFrame& frame, std::vector<cv::Point2f> left_px,
                          std::vector<cv::Point2f> right_px, int64_t now_ns);

  /// Called periodically while collecting: the stall message once when frames stopped for
  /// stall_ns (empty otherwise, and again after frames came back and stopped once more).
  std::string check_stall(int64_t now_ns);

  /// Ends the collection now (the page's button, a timeout): the verdict of the poses taken,
  /// or the reason there is none (fatal()).
  void finish_now();

  /// The state for the page, at monotonic time now_ns.
  nlohmann::json state(int64_t now_ns) const;

  /// The verdict when it passes (the file may be written), else an error saying why not.
  Result<Verdict> writable_verdict() const;
  /// Records where the file went (or why writing failed) for the page.
  void note_written(const std::string& path);
  void note_write_error(const std::string& error);

  /// The line the person holding the board should read now (hint, stall or failure).
  std::string message() const;
  /// The session ended without a verdict (why), or "" while it runs or has a verdict.
  const std::string& fatal() const { return fatal_; }
  /// True while frames have stopped for stall_ns (see check_stall).
  bool stalled() const { return stalled_; }
  /// The verdict, once computed.
  const std::optional<Verdict>& verdict() const { return verdict_; }
  /// The session, once the first frame fixed the image size.
  const std::optional<LiveCalibration>& session() const { return session_; }
  const StationParams& params() const { return params_; }

 private:
  StationStep feed(const StationFrame& frame, std::vector<cv::Point2f> left_px,
                   std::vector<cv::Point2f> right_px, int64_t now_ns);

  StationParams params_;
  std::optional<LiveCalibration> session_;
  cv::Size size_;
  std::string source_;
  std::vector<cv::Point2f> left_px_, right_px_;  // latest corners, for drawing
  uint64_t seq_ = 0;
  int64_t last_frame_ns_ = -1;
  bool stalled_ = false;
  std::string stall_text_;
  std::string fatal_;
  std::optional<Verdict> verdict_;
  std::string written_, write_error_;
};

}  // namespace stereoball::calibrate_live
