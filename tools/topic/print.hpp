#pragma once
// Human-readable text of every message type (images summarised, never dumped).

#include <string>

#include "stereoball/topics.hpp"

namespace stereoball::tools {

std::string to_text(const stereoball_msg_StereoFrame& m);
std::string to_text(const stereoball_msg_StereoCalibration& m);
std::string to_text(const stereoball_msg_BallDetection& m);
std::string to_text(const stereoball_msg_BallTrack& m);
std::string to_text(const stereoball_msg_VelocityCommand& m);
std::string to_text(const stereoball_msg_EmergencyStop& m);
std::string to_text(const stereoball_msg_GroundTruth& m);
std::string to_text(const stereoball_msg_ComponentStatus& m);

}  // namespace stereoball::tools
