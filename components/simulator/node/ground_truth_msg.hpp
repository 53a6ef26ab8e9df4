#pragma once
// Simulator core types <-> generated IDL structs (the stereo/frame message is filled by the
// frame library, stereo/frame/frame_msg.hpp). Outgoing structs point into the caller's
// buffers (strings): keep those alive until write() returns.

#include <cstdint>
#include <string>

#include "simulator/core/ground_truth.hpp"
#include "simulator/core/simulator.hpp"
#include "stereoball.h"

namespace stereoball::simulator {

/// sim/ground_truth message; scenario must outlive it.
stereoball_msg_GroundTruth ground_truth_to_msg(const GroundTruth& g, int64_t stamp_ns,
                                               const std::string& scenario);

/// A received command in simulated time: its age on the wall clock (now_wall_ns - stamp_ns,
/// never negative) is scaled by rate and subtracted from now_sim_ns.
VelocityCommand command_from_msg(const stereoball_msg_VelocityCommand& msg, int64_t now_wall_ns,
                                 int64_t now_sim_ns, double rate);

}  // namespace stereoball::simulator
