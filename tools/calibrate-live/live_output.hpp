#pragma once
// Writes the calibration a live session produced (terminal tool and browser page alike), with
// its figures, board and pose names in the file.

#include <string>

#include "common/util/result.hpp"
#include "live_calibration.hpp"

namespace stereoball::calibrate_live {

/// Writes verdict's calibration to path (.yaml/.yml/.xml/.json); refuses a verdict that did
/// not pass. Error names the file and the reason.
Status write_live_calibration(const std::string& path, const LiveParams& params,
                              const Verdict& verdict, const std::string& note);

}  // namespace stereoball::calibrate_live
