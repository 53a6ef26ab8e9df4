#pragma once
// One closed-loop run of a scenario (the shared offline loop with the motion controller
// driving), converted frame by frame to the samples the acceptance criteria judge.

#include <vector>

#include "acceptance.hpp"
#include "common/util/result.hpp"
#include "sim_loop.hpp"

namespace stereoball::bench_closed_loop {

/// The criteria's view of one loop frame.
Sample to_sample(const sim_loop::LoopFrame& frame);

/// Runs config (its drive is forced to the controller) to the end; error names the problem.
Result<std::vector<Sample>> run_closed_loop(sim_loop::LoopConfig config);

}  // namespace stereoball::bench_closed_loop
