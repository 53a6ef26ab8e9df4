#pragma once
// Figures of randomised runs per scene, per category value and in total: detection and track
// acceptance over the frames where the whole ball is in view in both eyes, and acceptance over
// the frames with no ball in view.

#include <cstdio>
#include <string>
#include <vector>

#include "simulator/core/randomize.hpp"
#include "tracking_run.hpp"

namespace stereoball::bench_tracking {

/// Counts of a group of runs.
struct SceneFigures {
  int scenes = 0;
  long fully_visible = 0;   ///< frames with the whole ball in view in both eyes
  long detected = 0;        ///< ... the detector's pair on the ball
  long accepted = 0;        ///< ... the tracker accepting a detection on the ball
  long no_ball = 0;         ///< frames with no ball in view
  long false_accepted = 0;  ///< ... the tracker accepting a detection anyway
};

/// Sums the frames of runs into one group's figures.
SceneFigures add_up(const std::vector<const RunResult*>& runs);

/// Prints one row per scene (with its categories), one table per category, then the total.
/// runs[i] is the run of scenes[i].
void print_scene_report(std::FILE* out, const std::vector<RunResult>& runs,
                        const std::vector<simulator::RandomScene>& scenes);

}  // namespace stereoball::bench_tracking
