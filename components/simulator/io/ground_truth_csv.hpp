#pragma once
// Ground truth as CSV rows (one per frame), for stereoball-sim --png-dir.

#include <string>

#include "simulator/core/ground_truth.hpp"

namespace stereoball::simulator {

/// The CSV header line (no trailing newline); columns match ground_truth_csv_row().
std::string ground_truth_csv_header();

/// One CSV row (no trailing newline): seq, time, ball world/camera/pixels, visibility, robot.
std::string ground_truth_csv_row(const GroundTruth& g);

}  // namespace stereoball::simulator
