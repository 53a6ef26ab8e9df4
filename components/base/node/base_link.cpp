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
    gate_.on_command({s->linear_mps, s->angular_radps}, s->stamp_ns, now);
    const GateOutput out = gate_.step(now);
    if (out.state == GateState::kEmergencyStop) {
      runner_.health().count("cmd_velocity_blocked_by_estop");
    }
    BaseCommand command;
    command.output = out;
    command.stamp_ns = s->stamp_ns;
    command.received_ns = now;
    command.seq = s->seq;
    command.key_id = s->auth.key_id;
    // The reader drops every sample whose MAC does not verify; keyless nothing is checked.
    command.authenticated = runner_.participant().auth().keyed() && s->auth.key_id != 0;
    command.source = s->source ? s->source : "";
    on_command_(command);
  }
}

void BaseLink::on_estop(const node::EstopState& state) {
  gate_.set_estop(state.engaged);
  // The stop takes effect now, not at the next command.
  const int64_t now = node::now_ns();
  BaseCommand command;
  command.output = gate_.step(now);
  command.stamp_ns = now;
  command.from_estop = true;
  command.received_ns = now;
  on_command_(command);
}

}  // namespace stereoball::base
