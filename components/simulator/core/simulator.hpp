#pragma once
// The simulator core: world dynamics + rendering + sensor + ground truth, stepped by time.

#include <opencv2/core.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "simulator/core/ground_truth.hpp"
#include "simulator/core/renderer.hpp"
#include "simulator/core/rig.hpp"
#include "simulator/core/scenario.hpp"
#include "simulator/core/sensor.hpp"
#include "simulator/core/sim_params.hpp"
#include "simulator/core/world.hpp"

namespace stereoball::simulator {

/// Where the calibration board was when each eye captured (calibration scenes).
struct BoardTruth {
  BoardPose left_pose;   ///< at sim_time_ns
  BoardPose right_pose;  ///< at right_time_ns
  int left_hold = -1;    ///< hold index at the left capture, -1 while moving
  int right_hold = -1;   ///< hold index at the right capture, -1 while moving
};

/// One simulated stereo frame: raw (distorted) BGR8 images of both eyes and the truth.
struct SimFrame {
  uint64_t seq = 0;
  int64_t sim_time_ns = 0;  ///< simulated time of the frame (end of exposure), ns = left capture
  /// Capture time of the right eye, ns: sim_time_ns plus the calibration scene's eye skew
  /// (free-running eyes), else sim_time_ns.
  int64_t right_time_ns = 0;
  cv::Mat left;   ///< CV_8UC3 BGR, raw left camera image
  cv::Mat right;  ///< CV_8UC3 BGR, raw right camera image
  GroundTruth truth;
  std::optional<BoardTruth> board;  ///< calibration scenes only
};

/// Runs two pieces of work and returns when both are done: one after the other (the default),
/// or on two threads when the caller has them (the simulator node renders the eyes at once).
using RunBoth = std::function<void(const std::function<void()>&, const std::function<void()>&)>;

/// Runs a, then b.
void run_in_turn(const std::function<void()>& a, const std::function<void()>& b);

/// Steps a scenario: step(command, t) advances the world to t and renders a frame there.
class Simulator {
 public:
  /// Params and scenario must be valid (validate() both first); see create().
  Simulator(const SimParams& params, const Scenario& scenario);

  /// Validates both and builds a simulator, or returns the first error.
  static Status check(const SimParams& params, const Scenario& scenario);

  /// Applies a new command (if any), advances to sim_time_ns (ns since scenario start,
  /// non-decreasing) and renders both eyes through run_both (the frame is the same either way).
  SimFrame step(const std::optional<VelocityCommand>& command, int64_t sim_time_ns,
                const RunBoth& run_both = run_in_turn);

  /// Advances the world without rendering (e.g. to skip ahead).
  void advance(const std::optional<VelocityCommand>& command, int64_t sim_time_ns);

  /// The true calibration of the simulated rig.
  const stereo::StereoCalibration& calibration() const { return rig_.calibration(); }
  /// The rig (intrinsics, poses).
  const StereoRig& rig() const { return rig_; }
  /// Current world state.
  const World& world() const { return world_; }
  /// The calibration scene with its poses drawn (nullopt for other scenarios).
  const std::optional<CalibrationScene>& calibration_scene() const { return board_scene_; }
  /// The scenario being run.
  const Scenario& scenario() const { return scenario_; }
  /// Simulated time between frames at the configured rate, ns.
  int64_t frame_period_ns() const;

 private:
  // Renders one eye at t_ns from a copy of the world at the start of the step (motion blur
  // replays the shutter interval on that copy), so the eyes share no state.
  void render_eye(Eye eye, World world, int64_t t_ns, cv::Mat& out);
  // Renders a calibration-scene frame (board poses at each eye's capture time).
  void step_board(SimFrame& f);
  // The instants rendered for a frame ending at t_ns: t_ns, or the motion-blur sub-frames.
  std::vector<int64_t> exposure_times(int64_t t_ns) const;

  SimParams params_;
  Scenario scenario_;
  StereoRig rig_;
  World world_;
  Renderer renderer_;
  Sensor sensor_;
  Occluders occluders_;
  std::optional<CalibrationScene> board_scene_;
  std::optional<BoardRenderer> board_renderer_;
  uint64_t seq_ = 0;
  cv::Mat sub_[2], acc_[2];  // per eye
};

}  // namespace stereoball::simulator
