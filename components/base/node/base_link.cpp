#include "base/node/base_link.hpp"

#include <string>

namespace stereoball::base {

BaseLink::BaseLink(node::Runner& runner, const VelocityGateParams& params,
                   std::function<void(const BaseCommand&)> on_command)
    : runner_(runner),
      gate_(params),
      on_command_(std::move(on_command)),
      commands_(runner.participant(), topics::kVelocityCommand),
      estop_(runner, [this](const node::EstopState& s) { on_estop(s); }) {
  runner_.on_data(commands_.handle(), [this] { on_velocity(); });
}

void BaseLink::on_velocity() {
  for (auto& s : commands_.take()) {
    const int64_t now = node::now_ns();
    runner_.health().count(std::string(topics::kVelocityCommand.spec.name));
    gate_.on_command({s->linear_mps, s->angular_radps}, now);
    const GateOutput out = gate_.step(now);
    if (out.state == GateState::kEmergencyStop) {
      runner_.health().count("cmd_velocity_blocked_by_estop");
    }
    on_command_({out, s->stamp_ns});
  }
}

void BaseLink::on_estop(const node::EstopState& state) {
  gate_.set_estop(state.engaged);
  // The stop takes effect now, not at the next command.
  const int64_t now = node::now_ns();
  on_command_({gate_.step(now), now});
}

}  // namespace stereoball::base
