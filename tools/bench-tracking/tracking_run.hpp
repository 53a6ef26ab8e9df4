#pragma once
// One offline run of the detection + tracking chain on a simulator scenario (the shared loop
// of tools/sim-loop: simulator core, ball detector pipeline, tracker core, optionally the
// motion controller core driving); every frame is compared with the ground truth.

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim_loop.hpp"

namespace stereoball::bench_tracking {

/// Everything one run needs (the shared offline loop's configuration).
using RunConfig = sim_loop::LoopConfig;
using sim_loop::Drive;

/// Per-frame outcome (kept so figures can be aggregated over scenarios).
struct FrameRecord {
  bool ball_present = false;        ///< scenario has a ball
  bool ball_visible = false;        ///< ball centre visible in both eyes (ground truth)
  bool ball_fully_visible = false;  ///< the whole ball in view in both eyes (ground truth)
  /// No ball in view: none in the scene, or its centre out of (or hidden in) both eyes and the
  /// detection, if any, not of it (a ball half out of the view may rightly be found)
  bool no_ball_in_view = false;
  bool raw_found = false;  ///< detector returned a stereo pair
  /// ... whose centre is within one ball radius of the truth (judged visible or not)
  bool raw_on_ball = false;
  bool accepted = false;          ///< tracker accepted this frame's detection
  bool accepted_on_ball = false;  ///< ... and the detection was on the ball
  double true_distance_m = 0;     ///< |ball centre| in the left rectified camera frame, m
  /// |detected - true| 3D position, m (-1 unless on the ball and the ball visible)
  double error_m = -1;
  double error_xyz_m[3] = {0, 0, 0};  ///< detected - true (x right, y down, z forward), m
  double cpu_ms = 0;                  ///< detector thread CPU time for this stereo frame, ms
  double wall_ms = 0;                 ///< detector wall time for this stereo frame, ms
  // Detail for the per-frame CSV (--frames-csv): where the ball was, what was found, why.
  std::int64_t stamp_ns = 0;                      ///< simulated capture time, ns
  double true_left_x_px = 0, true_left_y_px = 0;  ///< true centre, left rectified image, px
  double found_left_x_px = 0, found_left_y_px = 0, found_radius_px = 0;  ///< best left circle
  std::string detection_status;  ///< the pipeline's status name
  std::string detection_reason;  ///< the pipeline's reason
  std::string verdict;           ///< the tracker's verdict name
  std::string verdict_reason;    ///< the tracker's reason for it
  std::string track_state;       ///< the tracker's state after the frame
  std::string search;            ///< the pipeline's search that answered (SearchPath name)
  /// Why a frame with the whole ball in view was not accepted on the ball (empty otherwise):
  /// left_edges (the true outline's coverage on the left edge map below the detector's
  /// min_score), left_peaks (covered, and refinement seeded with the true circle stays on
  /// it, yet no left candidate on it: no examined peak there, or dropped for its colour),
  /// left_refine (covered, but even that perfect seed refines off the outline or below
  /// min_score: stripes, floor lines pull the fit), right_search (a left
  /// candidate on the ball, none in the right eye), pair_<status> (both eyes had it, the
  /// pairing checks said status), pair_other (another pair won), tracker (found, not accepted).
  std::string miss_cause;
  double true_radius_px = 0;   ///< mean radius of the true left outline, px
  double truth_coverage = -1;  ///< the detector's score of the true left outline (-1 unknown)
  /// On-ball detections: found minus true outline (centre x, centre y, mean radius) per eye,
  /// rectified px; tells which eye a 3D error comes from (NaN when not judged).
  double outline_error_left_px[3] = {NAN, NAN, NAN};
  double outline_error_right_px[3] = {NAN, NAN, NAN};
};

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
/// Called after every frame with its index (for dumping frames); may be empty.
using FrameSink = std::function<void(std::int64_t frame, const sim_loop::LoopFrame& f)>;
RunOutcome run_scenario(const RunConfig& config, const FrameSink& on_frame = {});

}  // namespace stereoball::bench_tracking
