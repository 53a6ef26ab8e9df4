#include "viewer/recording/derived_recording.hpp"

#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/log.hpp"
#include "stereoball/topics.hpp"
#include "viewer/core/foxglove_schemas.hpp"

namespace stereoball::viewer {

std::vector<recorder::RecordedTopic> derived_recorded_topics() {
  std::vector<recorder::RecordedTopic> out;
  for (const auto& t : foxglove::kDerivedTopics)
    out.push_back(
        {std::string(t.topic), std::string(t.schema_name), std::string(foxglove::schema_idl())});
  return out;
}

DerivedRecording::DerivedRecording(const dds::ParticipantOptions& participant,
                                   const DeriverParams& params, recorder::Recording& recording,
                                   size_t first_topic_index)
    : participant_(participant),
      deriver_(params),
      recording_(recording),
      first_topic_index_(first_topic_index) {
  thread_ = std::thread([this] { run(); });
}

DerivedRecording::~DerivedRecording() {
  stop();
}

void DerivedRecording::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void DerivedRecording::push(const std::vector<DerivedMessage>& messages) {
  const int64_t received = node::now_ns();
  for (const auto& m : messages) {
    const auto index = first_topic_index_ + static_cast<size_t>(m.channel);
    if (!recording_.push(index, m.cdr, static_cast<uint64_t>(received),
                         static_cast<uint64_t>(m.stamp_ns > 0 ? m.stamp_ns : received)))
      ++dropped_;
  }
}

void DerivedRecording::run() {
  try {
    dds::DataReader<stereoball_msg_StereoFrame> frames(participant_, topics::kStereoFrame);
    dds::DataReader<stereoball_msg_BallDetection> detections(participant_, topics::kBallDetection);
    dds::DataReader<stereoball_msg_BallTrack> tracks(participant_, topics::kBallTrack);
    dds::DataReader<stereoball_msg_GroundTruth> truth(participant_, topics::kGroundTruth);
    dds::DataReader<stereoball_msg_VelocityCommand> commands(participant_,
                                                             topics::kVelocityCommand);
    dds::DataReader<stereoball_msg_EmergencyStop> estop(participant_, topics::kEmergencyStop);
    dds::WaitSet waitset(participant_);
    std::vector<std::unique_ptr<dds::ReadCondition>> conditions;
    for (auto handle : {frames.handle(), detections.handle(), tracks.handle(), truth.handle(),
                        commands.handle(), estop.handle()}) {
      conditions.push_back(std::make_unique<dds::ReadCondition>(handle));
      waitset.attach(conditions.back()->handle(), 0);
    }
    while (!stop_) {
      waitset.wait(100'000'000);
      const int64_t now = node::monotonic_ns();
      {
        auto loaned = frames.take_loaned();
        if (auto newest = loaned.latest_valid()) push(deriver_.on_frame(loaned[*newest], now));
      }
      for (auto& s : detections.take(64)) push(deriver_.on_detection(*s));
      for (auto& s : tracks.take(64)) push(deriver_.on_track(*s, now));
      for (auto& s : truth.take(64)) push(deriver_.on_truth(*s, now));
      for (auto& s : commands.take(64)) deriver_.on_command(*s);
      for (auto& s : estop.take(64)) deriver_.on_estop(*s);
      bad_frames_ = deriver_.bad_frames();
    }
  } catch (const std::exception& e) {
    log::error("derived channels stopped: ", e.what());
  }
}

}  // namespace stereoball::viewer
