#include "stereoball/topics.hpp"

#include <array>

namespace stereoball::topics {

std::span<const TopicSpec> all() {
  static const std::array<TopicSpec, 8> kAll = {
      kStereoFrame.spec,     kStereoCalibration.spec, kBallDetection.spec, kBallTrack.spec,
      kVelocityCommand.spec, kEmergencyStop.spec,     kGroundTruth.spec,   kComponentStatus.spec};
  return kAll;
}

const TopicSpec* find(std::string_view name) {
  for (const auto& spec : all()) {
    if (spec.name == name) return &spec;
  }
  return nullptr;
}

}  // namespace stereoball::topics
