#include "base/core/velocity_gate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/util/enum_names.hpp"

namespace stereoball::base {

Status VelocityGateParams::validate() const {
  if (command_timeout_ns <= 0 || command_timeout_ns > 10'000'000'000) {
    return Error{"command_timeout_ns must be in (0, 1e10]"};
  }
  return {};
}

namespace {
constexpr util::EnumName<GateState> kGateStateNames[] = {
    {GateState::kDriving, "driving"},
    {GateState::kEmergencyStop, "emergency_stop"},
    {GateState::kStale, "stale"},
    {GateState::kNoCommand, "no_command"},
};
}  // namespace

std::string_view to_string(GateState state) {
  return util::name_of(kGateStateNames, state, "?");
}

std::optional<GateState> gate_state_from_string(std::string_view name) {
  return util::value_of(kGateStateNames, name);
}

int64_t command_expiry_ns(int64_t stamp_ns, int64_t received_ns, int64_t timeout_ns) {
  // The sender's stamp ages the command, so a late arrival does not restart its clock; the
  // receipt caps a stamp from the future (a sender's clock ahead of the base's).
  const int64_t from = std::min(stamp_ns, received_ns);
  int64_t expiry = 0;
  if (__builtin_add_overflow(from, timeout_ns, &expiry)) {
    expiry =
        timeout_ns < 0 ? std::numeric_limits<int64_t>::min() : std::numeric_limits<int64_t>::max();
  }
  return expiry;
}

bool command_fresh(int64_t stamp_ns, int64_t received_ns, int64_t now_ns, int64_t timeout_ns) {
  return now_ns <= command_expiry_ns(stamp_ns, received_ns, timeout_ns);
}

VelocityGate::VelocityGate(const VelocityGateParams& params) : params_(params) {}

void VelocityGate::on_command(const Velocity& command, int64_t stamp_ns, int64_t received_ns) {
  if (estop_) return;
  command_ = Velocity{std::isfinite(command.linear_mps) ? command.linear_mps : 0.0,
                      std::isfinite(command.angular_radps) ? command.angular_radps : 0.0};
  expiry_ns_ = command_expiry_ns(stamp_ns, received_ns, params_.command_timeout_ns);
}

void VelocityGate::set_estop(bool engaged) {
  // A command from before the stop must never resume motion after its release.
  if (engaged != estop_) command_.reset();
  estop_ = engaged;
}

GateOutput VelocityGate::step(int64_t now_ns) const {
  if (estop_) return {{}, GateState::kEmergencyStop};
  if (!command_) return {{}, GateState::kNoCommand};
  if (now_ns > expiry_ns_) return {{}, GateState::kStale};
  return {*command_, GateState::kDriving};
}

}  // namespace stereoball::base
