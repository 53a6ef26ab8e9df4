#pragma once
// The whole system in one process at simulated time: the simulator core renders raw stereo
// frames, the ball detector pipeline (rectification included) detects, the tracker core
// decides (its track fed back to the detector as a position prior for the next frame, as the
// ball_detector node does with ball/track), and either the scenario's script or the motion
// controller core drives the robot: event-driven as the node, each track answered when it
// reaches the controller (control_latency_ns after its frame), and at least
// controller_rate_hz without tracks; every command acts on the simulated base from its time on.
// Between the cores, detections and tracks pass through their IDL messages and the nodes' own
// conversions (the *_msg libraries), as in the deployed system. No DDS, no wall clock in the
// loop (only the detector timing figures read clocks).

#include <cstdint>
#include <deque>
#include <memory>
#include <optional>

#include <opencv2/core.hpp>

#include "ball_detector/pipeline/detector_params.hpp"
#include "ball_detector/pipeline/stereo_pipeline.hpp"
#include "common/util/result.hpp"
#include "motion_controller/core/controller_params.hpp"
#include "motion_controller/core/motion_controller.hpp"
#include "simulator/core/scenario.hpp"
#include "simulator/core/sim_params.hpp"
#include "simulator/core/simulator.hpp"
#include "stereoball.h"
#include "tracker/core/tracker.hpp"
#include "tracker/core/tracker_params.hpp"

namespace stereoball::sim_loop {

/// Who drives the robot during a run.
enum class Drive { kScript, kController };

/// Everything one run needs.
struct LoopConfig {
  simulator::SimParams sim;
  simulator::Scenario scenario;
  ball_detector::BallDetectorParams detector;
  tracker::TrackerParams tracker;
  motion_controller::MotionControllerParams controller;
  double controller_rate_hz = 20.0;  ///< minimum motion controller command rate, Hz
  /// Time from a frame's exposure to its track reaching the controller (detection, tracking,
  /// transport), simulated ns: the one-host p50 of `stereoball bench latency` rounded up.
  std::int64_t control_latency_ns = 10'000'000;
  Drive drive = Drive::kScript;  ///< scenario script, or the motion controller core
  double seconds = 10.0;         ///< simulated seconds to run
};

/// What happened at one camera frame.
struct LoopFrame {
  simulator::GroundTruth truth;              ///< true ball and robot at the frame time
  simulator::Vec3d ball_velocity_mps;        ///< true ball velocity, world frame, m/s
  ball_detector::StereoDetection detection;  ///< the detector pipeline's output
  tracker::Track track;                      ///< the tracker's output for this detection
  /// Latest controller command before this frame (Drive::kController, after the first one).
  std::optional<motion_controller::Command> command;
  std::int64_t command_stamp_ns = -1;  ///< issue time of command, simulated ns (-1 if none)
  double detector_cpu_ms = 0.0;        ///< detector thread CPU time for this stereo frame, ms
  double detector_wall_ms = 0.0;       ///< detector wall time for this stereo frame, ms
  cv::Mat left_raw, right_raw;  ///< the rendered frames (shared, not copied: valid until next step)
};

/// Steps the loop one camera frame at a time.
class SimLoop {
 public:
  /// Builds the loop, or an error naming the problem (scenario, params, calibration).
  static Result<std::unique_ptr<SimLoop>> create(const LoopConfig& config);

  /// Camera frames in the configured run (seconds x frame rate).
  std::int64_t frame_count() const { return frame_count_; }
  /// Frames stepped so far.
  std::int64_t frames_done() const { return next_frame_; }
  /// Issues the controller commands due up to the next frame, renders and processes that frame.
  LoopFrame step();
  /// The detector pipeline (its last frame's candidates and edges, for diagnostics).
  const ball_detector::StereoPipeline& pipeline() const { return pipeline_; }

 private:
  struct PendingTrack {
    motion_controller::TrackSample sample;
    std::int64_t arrival_ns = 0;  // when it reaches the controller, simulated ns
  };
  explicit SimLoop(const LoopConfig& config);
  void run_controller_until(std::int64_t until_ns);
  void apply(const motion_controller::Command& c, std::int64_t at_ns);
  std::optional<simulator::VelocityCommand> scripted_command(std::int64_t t_ns) const;

  LoopConfig config_;
  simulator::Simulator sim_;
  ball_detector::StereoPipeline pipeline_;
  tracker::Tracker tracker_;
  motion_controller::MotionController controller_;
  std::int64_t frame_period_ns_ = 0;
  std::int64_t tick_period_ns_ = 0;
  std::int64_t frame_count_ = 0;
  std::int64_t next_frame_ = 0;
  std::deque<PendingTrack> pending_tracks_;  // in arrival order
  std::optional<motion_controller::Command> last_command_;
  std::int64_t last_command_ns_ = -1;
  std::optional<ball_detector::TrackedBall> last_track_;  // fed back as the detector's prior
};

/// The ball/track message the tracker node publishes for track, captured and published at
/// stamp_ns (the tracker node's conversion; reason points into track: keep it alive).
stereoball_msg_BallTrack track_message(const tracker::Track& track, std::uint64_t seq,
                                       std::int64_t stamp_ns);

/// A tracker track as the detector's prior input: through ball/track and the ball detector
/// node's conversion (non-finite numbers invalidate the position).
ball_detector::TrackedBall to_tracked_ball(const tracker::Track& track, std::int64_t stamp_ns);

/// A tracker track as the controller's input: through ball/track and the motion controller
/// node's conversion (no casts between the two cores' enums; non-finite numbers invalidate it).
motion_controller::TrackSample to_controller(const tracker::Track& track, std::int64_t stamp_ns);

}  // namespace stereoball::sim_loop
