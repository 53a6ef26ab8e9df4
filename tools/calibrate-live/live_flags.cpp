#include "live_flags.hpp"

namespace stereoball::calibrate_live {

void add_live_flags(CLI::App& app, LiveFlags& o) {
  app.add_option("--board", o.board, "inner corners per row x per column")->capture_default_str();
  app.add_option("--square-mm", o.square_mm, "chessboard square side, mm (sets the unit of T)")
      ->check(CLI::Range(1.0, 1000.0))
      ->capture_default_str();
  app.add_option("--poses", o.poses, "poses to take before the verdict")
      ->check(CLI::Range(6, 200))
      ->capture_default_str();
  app.add_option("--still-s", o.still_s, "how long the board must stand still in both eyes, s")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--max-motion-px", o.max_motion_px,
                 "largest corner motion that still counts as still, px")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app.add_option("--max-rms-px", o.max_rms_px, "verdict: largest stereo RMS, px")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  app.add_option("--max-row-error-px", o.max_row_error_px,
                 "verdict: largest mean rectified row error, px")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  app.add_option("--baseline-m", o.baseline_m,
                 "the rig's measured baseline, m: the verdict fails beyond +-10 % (0 = unchecked)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  app.add_option("--timeout-s", o.timeout_s,
                 "give up collecting poses after this long and judge the ones taken, s")
      ->check(CLI::Range(1.0, 86400.0))
      ->capture_default_str();
  app.add_option("--stall-s", o.stall_s, "say so when no frame arrived for this long, s")
      ->check(CLI::Range(0.1, 600.0))
      ->capture_default_str();
  app.add_option("-o,--output", o.output, "calibration file to write (.yaml)");
}

Result<StationParams> station_params(const LiveFlags& o) {
  const auto board = stereo::parse_board_size(o.board);
  if (!board)
    return Error{"--board '" + o.board + "': expected COLSxROWS of inner corners, e.g. 9x6"};
  if (o.output.empty()) return Error{"-o FILE: the calibration file to write is required"};
  StationParams p;
  LiveParams& l = p.live;
  l.board.inner_corners = *board;
  l.board.square_m = o.square_mm * 1e-3;
  l.target_poses = o.poses;
  l.still.still_ns = static_cast<int64_t>(o.still_s * 1e9);
  l.still.max_motion_px = o.max_motion_px;
  l.max_rms_px = o.max_rms_px;
  l.max_row_error_px = o.max_row_error_px;
  if (o.baseline_m > 0) {
    l.min_baseline_m = o.baseline_m * 0.9;
    l.max_baseline_m = o.baseline_m * 1.1;
  }
  p.stall_ns = static_cast<int64_t>(o.stall_s * 1e9);
  if (auto st = l.validate(); !st) return Error{st.error()};
  return p;
}

}  // namespace stereoball::calibrate_live
