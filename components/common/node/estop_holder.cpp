#include "common/node/estop_holder.hpp"

#include "common/util/log.hpp"

namespace stereoball::node {

EstopHolder::EstopHolder(Runner& runner, std::function<void(const EstopState&)> on_change)
    : runner_(runner),
      reader_(runner.participant(), topics::kEmergencyStop),
      relay_(runner.participant(), topics::kEmergencyStop),
      on_change_(std::move(on_change)) {
  runner_.on_data(reader_.handle(), [this] { on_data(); });
  runner_.health().set_counter("estop_engaged", 0);
}

void EstopHolder::on_data() {
  // The reader delivers only states newer than the one held (by authenticated stamp), so the
  // last sample taken is the operator's latest decision.
  for (auto& s : reader_.take()) {
    runner_.health().count(std::string(topics::kEmergencyStop.spec.name));
    relay_.forward(*s);
    const bool changed = s->engaged != state_.engaged;
    state_ = EstopState{s->engaged, s->auth.stamp_ns, s->reason ? s->reason : ""};
    if (!changed) continue;
    if (state_.engaged) {
      log::warn("emergency stop engaged: ", state_.reason);
    } else {
      log::info("emergency stop released: ", state_.reason);
    }
    on_change_(state_);
  }
  runner_.health().set_counter("estop_engaged", state_.engaged ? 1 : 0);
}

}  // namespace stereoball::node
