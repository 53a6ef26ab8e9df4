#pragma once
// The flags of a live calibration, shared by `stereoball calibrate live --terminal` and
// `stereoball view --calibrate` (which `stereoball calibrate live` starts), so both take the
// same options with the same checks.

#include "common/util/cli11.hpp"

#include <string>

#include "common/util/result.hpp"
#include "live_station.hpp"

namespace stereoball::calibrate_live {

/// The options as given on the command line.
struct LiveFlags {
  std::string board = "9x6";
  double square_mm = 25.0;
  int poses = 15;
  double still_s = 0.3;
  double max_motion_px = 0.5;
  double max_rms_px = 0.5;
  double max_row_error_px = 0.3;
  double baseline_m = 0;
  double timeout_s = 600;
  double stall_s = 2.0;
  std::string output;
};

/// Adds --board, --square-mm, --poses, --still-s, --max-motion-px, --max-rms-px,
/// --max-row-error-px, --baseline-m, --timeout-s, --stall-s and -o/--output to app.
void add_live_flags(CLI::App& app, LiveFlags& flags);

/// The station's parameters from the flags; an error naming the flag when they do not fit.
Result<StationParams> station_params(const LiveFlags& flags);

}  // namespace stereoball::calibrate_live
