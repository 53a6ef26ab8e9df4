#pragma once
// The ball_detector process: stereo/frame + stereo/calibration in, one ball/detection per
// processed frame out. Always works on the newest frame (keep-last-1) and counts the rest.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "ball_detector/node/frame_gaps.hpp"
#include "ball_detector/node/frame_times.hpp"
#include "ball_detector/node/task_helper.hpp"
#include "ball_detector/pipeline/calibration_gate.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/log.hpp"
#include "stereo/core/eye_order.hpp"
#include "stereo/frame/frame_decoder.hpp"
#include "stereo/frame/frame_transport.hpp"

namespace stereoball::ball_detector {

/// Wires the stereo pipeline to its topics on a runner.
class BallDetectorNode {
 public:
  /// Creates readers/writers on runner's participant and registers callbacks; frame_times_path
  /// not empty: each frame's stage times go there (FrameTimesLog).
  /// pin_threads: the frame thread and the task helper each on a CPU of its own (main's
  /// default; off in tests, whose process must not be pinned).
  BallDetectorNode(node::Runner& runner, const BallDetectorParams& params,
                   const std::string& frame_times_path = "", bool pin_threads = false);

 private:
  // A validated calibration and who published it.
  struct CalibrationFrom {
    stereo::StereoCalibration calib;
    std::string source;
  };
  void on_calibration();
  void apply_calibration(const CalibrationFrom& calibration);
  void reject_calibration(const std::string& source, const std::string& problem);
  void check_frame_size(const stereoball_msg_StereoFrame& frame);
  void check_input(std::int64_t now_ns);
  void on_frames();
  void process(const stereoball_msg_StereoFrame& frame);
  /// The eye-order check on a frame whose right eye may be made only in part (made whole when
  /// the check is due).
  void check_eye_order(const cv::Mat& left, stereo::RowSource& right, bool rectified);
  void check_eye_order(const cv::Mat& left, const cv::Mat& right, bool rectified);
  std::optional<PositionPrior> prior_for(std::int64_t frame_stamp_ns);
  void count_skipped(std::uint64_t seq, std::uint64_t batch_skipped);
  void check_transport(const stereoball_msg_StereoFrame& frame);
  void report_gaps(std::int64_t now_ns);
  void report_pinning();
  void report_problem(const StereoDetection& det, std::uint64_t seq, std::int64_t now_ns);
  void publish(const StereoDetection& det, const stereoball_msg_StereoFrame& frame,
               std::int64_t start_mono_ns);

  node::Runner& runner_;
  TaskHelper helper_;  // the pipeline's tasks on the other core (declared first: outlives it)
  bool pinning_reported_ = false;  // the pinning's outcome logged
  StereoPipeline pipeline_;
  CalibrationGate gate_;
  std::optional<CalibrationFrom> pending_calibration_;  // held back until frames fit it
  // First frames of each calibration: are the cameras swapped? (3 looks, 30 frames apart: each
  // costs a few hundred ms on a loaded machine, so not every 100 frames as camera_server does)
  stereo::EyeOrderWatch eye_order_{3, 30};
  stereo::FrameDecoder decoder_;
  dds::DataReader<stereoball_msg_StereoFrame> frames_;
  dds::DataReader<stereoball_msg_StereoCalibration> calibration_;
  dds::DataReader<stereoball_msg_BallTrack> tracks_;  // fed back: where the ball is expected
  std::optional<TrackedBall> last_track_;
  BallDetectorParams params_;
  dds::DataWriter<stereoball_msg_BallDetection> detections_;
  std::optional<std::uint64_t> last_seq_;
  std::int64_t last_frame_ns_ = 0;  // wall clock of the last frame, ns since epoch
  std::uint64_t processed_ = 0;
  std::uint64_t found_ = 0;
  std::uint64_t bad_frames_ = 0;
  std::uint64_t uncalibrated_frames_ = 0;
  std::uint64_t bad_calibrations_ = 0;
  log::Throttle bad_frame_log_{1'000'000'000};
  log::Throttle uncalibrated_log_{1'000'000'000};
  std::uint64_t bad_frames_logged_ = 0;
  // Frames that do not cross the transport: sample size vs receive buffer, and seq gaps.
  FrameGaps gaps_;
  std::int64_t idle_since_ns_ = 0;  // monotonic end of the last callback's work (0 = none yet)
  std::optional<stereo::TransportLimits> transport_;  // read at the first frame
  std::uint64_t largest_sample_bytes_ = 0;
  bool oversize_reported_ = false;
  log::Throttle gap_log_{60'000'000'000};
  std::unique_ptr<FrameTimesLog> times_;  // each frame's stage times, when asked for
};

}  // namespace stereoball::ball_detector
