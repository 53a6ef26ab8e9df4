#pragma once
// `stereoball record`'s derived Foxglove channels: its own participant and thread subscribe
// to frames, detections, tracks, ground truth, commands and e-stop, run a Deriver and push
// what it returns into the recording as extra channels (foxglove.CompressedImage per eye,
// ImageAnnotations, SceneUpdate, FrameTransforms; CDR with omgidl schemas). Nothing here
// can slow the recording of the raw topics: it has its own reader per topic and thread.

#include <atomic>
#include <cstdint>
#include <memory>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "recorder/io/recording.hpp"
#include "viewer/bridge/derived_channels.hpp"

namespace stereoball::viewer {

/// The derived channels as topics to record (append them after the raw topics).
std::vector<recorder::RecordedTopic> derived_recorded_topics();

class DerivedRecording {
 public:
  /// Derived channel i goes to recording topic first_topic_index + i.
  DerivedRecording(const dds::ParticipantOptions& participant, const DeriverParams& params,
                   recorder::Recording& recording, size_t first_topic_index);
  ~DerivedRecording();
  DerivedRecording(const DerivedRecording&) = delete;
  DerivedRecording& operator=(const DerivedRecording&) = delete;
  /// Stops the thread (call before stopping the recording).
  void stop();
  /// Derived messages the recording refused (queue full) and frames that could not be encoded.
  uint64_t dropped() const { return dropped_.load(); }
  uint64_t bad_frames() const { return bad_frames_.load(); }

 private:
  void run();
  void push(const std::vector<DerivedMessage>& messages);
  dds::DomainParticipant participant_;
  Deriver deriver_;
  recorder::Recording& recording_;
  size_t first_topic_index_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> dropped_{0};
  std::atomic<uint64_t> bad_frames_{0};
  std::thread thread_;
};

}  // namespace stereoball::viewer
