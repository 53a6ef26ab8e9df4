#pragma once
// The replay tests' input: a short simulator run turned into an MCAP recording without any
// timing dependence. Frames are rendered by the simulator core at simulated time; detections
// and tracks come from the same cores the nodes use (StereoPipeline, Tracker), so every
// message is a pure function of the scenario. Messages are serialized to CDR through a local
// DDS reader (exactly the bytes a node would send) and written with the recorder.

#include <cstdint>
#include <optional>
#include <string>

#include "common/util/result.hpp"

namespace stereoball::replay {

/// Frames in the recording (30 Hz simulated: 1.5 s).
inline constexpr int kReplayFrames = 45;
/// Extra ball/track samples after the frames: the last track held (ball still) for 0.5 s.
inline constexpr int kHeldTrackFrames = 15;
/// Capture stamp of the first frame, ns since the epoch (fixed, so references are stable).
inline constexpr std::int64_t kReplayEpochNs = 1'700'000'000'000'000'000;

/// Writes the recording to path (topics stereo/calibration, stereo/frame, ball/detection,
/// ball/track); DDS is used on domain/partition only to serialize. Error text on failure.
Status make_replay_recording(const std::string& path, int domain, const std::string& partition);

}  // namespace stereoball::replay
