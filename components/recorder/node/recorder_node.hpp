#pragma once
// The recorder's DDS side: one serialized reader per chosen topic feeding a Recording (log
// time = receive time, publish time = the source stamp), the samples DDS lost counted per
// channel, and optionally the derived Foxglove channels (viewer/recording). The command line,
// file naming and progress printing stay with the tool (tools/record).

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/serialized.hpp"
#include "common/node/node_runner.hpp"
#include "recorder/io/recording.hpp"
#include "stereoball/topics.hpp"
#include "viewer/recording/derived_recording.hpp"

namespace stereoball::recorder {

/// Reader QoS for recording: the table's, with a deeper history so bursts between takes are
/// not overwritten, and no deadline requirement.
topics::QosSpec recording_qos(const topics::TopicSpec& spec);

/// Wires recorded topics to a Recording on a runner's participant and thread.
class RecorderNode {
 public:
  /// specs[i] is recorded as channel i of recording; with derive, the derived channels are
  /// the recording's channels after them, fed from a participant of their own (options).
  RecorderNode(node::Runner& runner, const dds::ParticipantOptions& options,
               const std::vector<const topics::TopicSpec*>& specs, Recording& recording,
               const std::optional<viewer::DeriverParams>& derive);

  /// Adds the samples DDS lost (history overwritten, rejected) since the last call to lost().
  void update_lost();
  /// Samples lost in DDS per channel of the recording (derived channels: always 0).
  const std::vector<uint64_t>& lost() const { return lost_; }
  /// Stops the derived channels and closes the readers; call before stopping the recording.
  void stop();

 private:
  void on_samples(size_t channel);

  node::Runner& runner_;
  std::vector<const topics::TopicSpec*> specs_;
  Recording& recording_;
  std::vector<std::unique_ptr<dds::SerializedReader>> readers_;
  std::unique_ptr<viewer::DerivedRecording> derived_;
  std::vector<uint64_t> lost_;
};

}  // namespace stereoball::recorder
