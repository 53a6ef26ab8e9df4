#pragma once
// EstopHolder: the emergency stop as one node obeys it. It takes cmd/estop (authenticated:
// only the newest operator-signed state is delivered) and re-publishes that sample unchanged
// on its own transient-local writer, so the stop survives the restart of any other node,
// the operator's tool included. Every node that obeys the stop holds it this way.

#include <cstdint>
#include <functional>
#include <string>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"

namespace stereoball::node {

/// The latched e-stop state a node holds.
struct EstopState {
  bool engaged = false;
  int64_t stamp_ns = 0;  ///< the operator's authenticated stamp of this state (0 = never set)
  std::string reason;
};

class EstopHolder {
 public:
  /// on_change(state) runs on the loop thread whenever the held state changes.
  EstopHolder(Runner& runner, std::function<void(const EstopState&)> on_change);
  const EstopState& state() const { return state_; }
  bool engaged() const { return state_.engaged; }

 private:
  void on_data();

  Runner& runner_;
  dds::DataReader<stereoball_msg_EmergencyStop> reader_;
  dds::DataWriter<stereoball_msg_EmergencyStop> relay_;
  std::function<void(const EstopState&)> on_change_;
  EstopState state_;
};

}  // namespace stereoball::node
