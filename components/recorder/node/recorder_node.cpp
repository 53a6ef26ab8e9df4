#include "recorder/node/recorder_node.hpp"

#include <algorithm>

#include "common/dds/reader.hpp"

namespace stereoball::recorder {

topics::QosSpec recording_qos(const topics::TopicSpec& spec) {
  topics::QosSpec q = spec.qos;
  q.history_depth = std::max(q.history_depth, 32);
  q.deadline_ns = 0;
  return q;
}

RecorderNode::RecorderNode(node::Runner& runner, const dds::ParticipantOptions& options,
                           const std::vector<const topics::TopicSpec*>& specs, Recording& recording,
                           const std::optional<viewer::DeriverParams>& derive)
    : runner_(runner), specs_(specs), recording_(recording), lost_(recording.counters().size(), 0) {
  for (size_t i = 0; i < specs_.size(); ++i) {
    readers_.push_back(std::make_unique<dds::SerializedReader>(runner_.participant(), *specs_[i],
                                                               recording_qos(*specs_[i])));
    runner_.on_data(readers_.back()->handle(), [this, i] { on_samples(i); });
  }
  if (derive) {
    derived_ =
        std::make_unique<viewer::DerivedRecording>(options, *derive, recording_, specs_.size());
  }
}

void RecorderNode::on_samples(size_t channel) {
  std::vector<dds::SerializedSample> samples;
  readers_[channel]->take(samples, 256);
  const int64_t received = node::now_ns();
  for (auto& s : samples) {
    const uint64_t publish = s.source_stamp_ns > 0 ? s.source_stamp_ns : received;
    if (!recording_.push(channel, std::move(s.cdr), received, publish)) {
      runner_.health().drop(specs_[channel]->name.data(), 1);
    }
  }
}

void RecorderNode::update_lost() {
  for (size_t i = 0; i < readers_.size(); ++i) {
    lost_[i] += dds::take_lost_count(readers_[i]->handle());
  }
}

void RecorderNode::stop() {
  if (derived_) derived_->stop();
  readers_.clear();
}

}  // namespace stereoball::recorder
