#pragma once
// One offline run of the detection + tracking chain on a simulator scenario: simulator core
// renders raw stereo frames at simulated time, the ball detector pipeline (rectification
// included) detects, the tracker core decides; every frame is compared with the ground truth.
// No DDS, no wall clock in the chain (only the timing figures read clocks).

#include <cstdint>
#include <string>
#include <vector>

#include "ball_detector/node/detector_params.hpp"
#include "motion_controller/core/controller_params.hpp"
#include "simulator/core/scenario.hpp"
#include "simulator/core/sim_params.hpp"
#include "tracker/core/tracker_params.hpp"

namespace stereoball::bench_tracking {

/// Who drives the robot during a run.
enum class Drive { kScript, kController };

/// Everything one run needs.
struct RunConfig {
  simulator::SimParams sim;
  simulator::Scenario scenario;
  ball_detector::BallDetectorParams detector;
  tracker::TrackerParams tracker;
  motion_controller::MotionControllerParams controller;
  Drive drive = Drive::kScript;  ///< scenario script, or the motion controller core on tracks
  double seconds = 10.0;         ///< simulated seconds to run
};

/// Per-frame outcome (kept so figures can be aggregated over scenarios).
struct FrameRecord {
  bool ball_present = false;          ///< scenario has a ball
  bool ball_visible = false;          ///< ball centre visible in both eyes (ground truth)
  bool raw_found = false;             ///< detector returned a stereo pair
  bool raw_on_ball = false;           ///< ... whose left centre is within kOnBallPx of the truth
  bool accepted = false;              ///< tracker accepted this frame's detection
  bool accepted_on_ball = false;      ///< ... and the detection was on the ball
  double true_distance_m = 0;         ///< |ball centre| in the left rectified camera frame, m
  double error_m = -1;                ///< |detected - true| 3D position, m (-1 if not on the ball)
  double error_xyz_m[3] = {0, 0, 0};  ///< detected - true (x right, y down, z forward), m
  double cpu_ms = 0;                  ///< detector thread CPU time for this stereo frame, ms
  double wall_ms = 0;                 ///< detector wall time for this stereo frame, ms
};

/// Largest distance of the detected left centre from the true one to count as "on the ball".
inline constexpr double kOnBallPx = 5.0;

/// All frames of one scenario run.
struct RunResult {
  std::string scenario;
  std::vector<FrameRecord> frames;
};

/// Runs the chain; error text names the problem (invalid scenario, params, calibration).
struct RunOutcome {
  RunResult result;
  std::string error;  ///< empty on success
};
RunOutcome run_scenario(const RunConfig& config);

/// Median (q = 0.5), p95 (q = 0.95) etc. by nearest rank; 0 for an empty list.
double percentile(std::vector<double> values, double q);

}  // namespace stereoball::bench_tracking
