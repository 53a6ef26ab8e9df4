#pragma once
// Builds one fully populated sample of every message type (every field set to a value
// derived from a seed, no field left zero), for round-trip tests and benchmarks.

#include <deque>
#include <string>
#include <vector>

#include "stereoball/topics.hpp"

namespace stereoball::testing {

/// Owns the strings and buffers that populated C samples point into.
struct SampleStorage {
  std::deque<std::string> strings;
  std::deque<std::vector<uint8_t>> bytes;
  std::deque<std::vector<double>> doubles;
  std::deque<std::vector<stereoball_msg_TopicRate>> rates;
  std::deque<std::vector<stereoball_msg_Counter>> counters;
  char* str(std::string s) { return strings.emplace_back(std::move(s)).data(); }
};

void fill(stereoball_msg_StereoFrame& m, SampleStorage& s, uint32_t seed, uint32_t width = 640,
          uint32_t height = 480);
void fill(stereoball_msg_StereoCalibration& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_BallDetection& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_BallTrack& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_VelocityCommand& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_EmergencyStop& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_GroundTruth& m, SampleStorage& s, uint32_t seed);
void fill(stereoball_msg_ComponentStatus& m, SampleStorage& s, uint32_t seed);

}  // namespace stereoball::testing
