#pragma once
// Simulator core types <-> generated IDL structs. Outgoing structs point into the caller's
// buffers (images, distortion vectors, strings): keep those alive until write() returns.

#include <cstdint>
#include <string>
#include <vector>

#include "simulator/core/ground_truth.hpp"
#include "simulator/core/simulator.hpp"
#include "stereo/core/calibration.hpp"
#include "stereoball.h"

namespace stereoball::simulator {

/// stereo/frame message (bgr8, raw eyes) of a simulated frame; frame and source must outlive it.
stereoball_msg_StereoFrame frame_to_msg(const SimFrame& frame, int64_t stamp_ns,
                                        const std::string& source);

/// stereo/frame message carrying compressed eyes: encoding ("jpeg"/"png"), step_bytes 0, the
/// decoded size of the frame's images, data = one complete stream per eye. frame, encoding,
/// left, right and source must outlive it.
stereoball_msg_StereoFrame encoded_frame_to_msg(const SimFrame& frame, const std::string& encoding,
                                                const std::vector<uint8_t>& left,
                                                const std::vector<uint8_t>& right, int64_t stamp_ns,
                                                const std::string& source);

/// sim/ground_truth message; scenario must outlive it.
stereoball_msg_GroundTruth ground_truth_to_msg(const GroundTruth& g, int64_t stamp_ns,
                                               const std::string& scenario);

/// A received command in simulated time: its age on the wall clock (now_wall_ns - stamp_ns,
/// never negative) is scaled by rate and subtracted from now_sim_ns.
VelocityCommand command_from_msg(const stereoball_msg_VelocityCommand& msg, int64_t now_wall_ns,
                                 int64_t now_sim_ns, double rate);

}  // namespace stereoball::simulator
