#include "motion_controller/node/motion_controller_node.hpp"

#include <string>

#include "common/util/log.hpp"
#include "motion_controller/node/command_msg.hpp"

namespace stereoball::motion_controller {
namespace {

// How often the node looks for input that just went stale and for a due minimum-rate command,
// ns: commands are never further apart than 1 / rate_hz, and a stale stop goes out within it.
constexpr std::int64_t kCheckPeriodNs = 5'000'000;
// A run of bad stamps of one kind is logged at its first sample and then every this many.
constexpr std::uint64_t kBadStampLogEvery = 100;

}  // namespace

MotionControllerNode::MotionControllerNode(node::Runner& runner,
                                           const MotionControllerNodeParams& params)
    : runner_(runner),
      controller_(params.controller),
      period_ns_(static_cast<std::int64_t>(1e9 / params.rate_hz)),
      tracks_(runner.participant(), topics::kBallTrack),
      estop_(runner, [this](const node::EstopState& s) { on_estop(s); }),
      commands_(runner.participant(), topics::kVelocityCommand) {
  runner_.on_data(tracks_.handle(), [this] { on_tracks(); });
  // Tracks are answered when they arrive; this timer only keeps the minimum rate and sends the
  // stale stop when it happens, not up to a period later.
  runner_.every(kCheckPeriodNs, [this](std::int64_t now_ns) {
    const bool newly_stale = last_mode_ != Mode::kStale && controller_.input_stale(now_ns);
    if (newly_stale || controller_.minimum_rate_due(now_ns, period_ns_, kCheckPeriodNs)) {
      publish(controller_.step(now_ns), now_ns);
    }
  });
  runner_.health().set_state(false, "waiting for ball/track");
}

void MotionControllerNode::on_tracks() {
  // Only the newest state matters: an older sample in the same batch is already superseded.
  auto latest = tracks_.take_latest();
  if (!latest) return;
  runner_.health().count(std::string(topics::kBallTrack.spec.name));
  const stereoball_msg_BallTrack& msg = **latest;
  const std::int64_t now = node::now_ns();
  const auto response = controller_.on_track(to_sample(msg), now);
  if (response.command) {
    bad_stamps_in_a_row_ = 0;
    publish(*response.command, now);
    return;
  }
  if (response.check == StampCheck::kRepeated) {
    runner_.health().count("repeated_track_stamps");
    return;
  }
  report_bad_stamp(msg, response.check, now);
}

void MotionControllerNode::report_bad_stamp(const stereoball_msg_BallTrack& msg, StampCheck check,
                                            std::int64_t now_ns) {
  const std::string what = "ball/track frame " + std::to_string(msg.frame_seq) +
                           ": capture_stamp_ns " + std::to_string(msg.capture_stamp_ns) + " is " +
                           std::string(to_string(check)) + " (receiver clock " +
                           std::to_string(now_ns) + "); no command built on it";
  runner_.health().error("bad_track_stamp", what);
  // A new kind of problem is always logged; a run of the same one once in a while.
  if (check != last_bad_check_) bad_stamps_in_a_row_ = 0;
  last_bad_check_ = check;
  if (bad_stamps_in_a_row_++ % kBadStampLogEvery == 0) log::warn(what);
}

void MotionControllerNode::on_estop(const node::EstopState& state) {
  // The holder logged the change; a new stop goes out at once, not at the next check.
  const bool newly_engaged = state.engaged && !controller_.estop_engaged();
  controller_.on_estop(state.engaged);
  if (newly_engaged) {
    const std::int64_t now = node::now_ns();
    publish(controller_.step(now), now);
  }
}

void MotionControllerNode::publish(const Command& c, std::int64_t now_ns) {
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
