#include "motion_controller/node/motion_controller_node.hpp"

#include <string>

#include "common/util/log.hpp"
#include "motion_controller/node/command_conversion.hpp"

namespace stereoball::motion_controller {
namespace {

// How often the node looks for input that just went stale, ns.
constexpr std::int64_t kStaleWatchPeriodNs = 10'000'000;

}  // namespace

MotionControllerNode::MotionControllerNode(node::Runner& runner,
                                           const MotionControllerNodeParams& params)
    : runner_(runner),
      controller_(params.controller),
      tracks_(runner.participant(), topics::kBallTrack),
      estop_(runner, [this](const node::EstopState& s) { on_estop(s); }),
      commands_(runner.participant(), topics::kVelocityCommand) {
  runner_.on_data(tracks_.handle(), [this] { on_tracks(); });
  const auto period_ns = static_cast<std::int64_t>(1e9 / params.rate_hz);
  runner_.every(period_ns, [this](std::int64_t now_ns) { tick(now_ns); });
  // Safety stops go out when they happen, not at the next regular tick (up to a period later).
  runner_.every(kStaleWatchPeriodNs, [this](std::int64_t now_ns) {
    if (last_mode_ != Mode::kStale && controller_.input_stale(now_ns)) tick(now_ns);
  });
  runner_.health().set_state(false, "waiting for ball/track");
}

void MotionControllerNode::on_tracks() {
  // Only the newest state matters for the next command.
  if (auto latest = tracks_.take_latest()) {
    controller_.on_track(to_sample(**latest), node::now_ns());
    runner_.health().count(std::string(topics::kBallTrack.spec.name));
  }
}

void MotionControllerNode::on_estop(const node::EstopState& state) {
  // The holder logged the change; a new stop goes out at once, not at the next tick.
  controller_.on_estop(state.engaged);
  if (state.engaged) tick(node::now_ns());
}

void MotionControllerNode::tick(std::int64_t now_ns) {
  const Command c = controller_.step(now_ns);
  stereoball_msg_VelocityCommand out{};
  to_message(c, seq_++, now_ns, out);
  commands_.write(out);
  runner_.health().count(std::string(topics::kVelocityCommand.spec.name));
  const bool healthy = c.mode != Mode::kStale && c.mode != Mode::kWaiting;
  runner_.health().set_state(healthy, std::string(to_string(c.mode)));
  if (c.mode != last_mode_) {
    log::info("mode ", to_string(last_mode_), " -> ", to_string(c.mode));
    last_mode_ = c.mode;
  }
}

}  // namespace stereoball::motion_controller
