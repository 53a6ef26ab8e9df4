#pragma once
// Conversion between the IDL messages (ball/track, cmd/velocity) and the
// motion controller core's value types.

#include <cstdint>

#include "motion_controller/core/types.hpp"
#include "stereoball.h"

namespace stereoball::motion_controller {

/// The track state and side of ball/track; unknown values give kIdle / kUnknown.
TrackState from_msg(stereoball_msg_TrackState s);
Side from_msg(stereoball_msg_Side s);

/// The fields of ball/track the controller uses; non-finite numbers make the position invalid.
TrackSample to_sample(const stereoball_msg_BallTrack& msg);

/// Fills cmd/velocity; out.source points at a static string.
void to_message(const Command& command, std::uint64_t seq, std::int64_t stamp_ns,
                stereoball_msg_VelocityCommand& out);

}  // namespace stereoball::motion_controller
