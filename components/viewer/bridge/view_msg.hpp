#pragma once
// Incoming messages (generated IDL types) into the viewer's plain values.

#include "stereoball.h"
#include "viewer/core/view_model.hpp"

namespace stereoball::viewer {

Detection to_view(const stereoball_msg_BallDetection& m);
Track to_view(const stereoball_msg_BallTrack& m);
Command to_view(const stereoball_msg_VelocityCommand& m);
Estop to_view(const stereoball_msg_EmergencyStop& m);
Truth to_view(const stereoball_msg_GroundTruth& m);
Health to_view(const stereoball_msg_ComponentStatus& m);

}  // namespace stereoball::viewer
