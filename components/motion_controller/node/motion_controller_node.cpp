#include "motion_controller/node/motion_controller_node.hpp"

#include <algorithm>
#include <string>

#include "common/util/log.hpp"
#include "motion_controller/node/command_msg.hpp"

namespace stereoball::motion_controller {
namespace {

// A minimum-rate command goes out once this much less than a period passed without one, as
// when the node polled every 5 ms: a track due at about the same time then does not leave a gap
// of more than the period.
constexpr std::int64_t kMinimumRateSlackNs = 5'000'000;
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
  // stale stop at the instant the input goes stale. It is set for exactly that instant after
  // every sample and command, so the node wakes only when there is something to do (a timer
  // polling every 5 ms woke it ~200 times a second, more often than the tracks arrive).
  deadline_timer_ = runner_.one_shot([this](std::int64_t now_ns) { on_deadline(now_ns); });
  runner_.wake_at(deadline_timer_, node::monotonic_ns());  // the first (waiting) command
  runner_.health().set_state(false, "waiting for ball/track");
}

void MotionControllerNode::on_deadline(std::int64_t now_ns) {
  bool due = controller_.minimum_rate_due(now_ns, period_ns_, kMinimumRateSlackNs);
  if (controller_.input_stale(now_ns)) {
    // The stale stop goes out once per silence (the mode says so unless the e-stop is held);
    // after it the minimum rate repeats it.
    due = due || (last_mode_ != Mode::kStale && stale_handled_ != controller_.stale_at_ns());
    stale_handled_ = controller_.stale_at_ns();
  }
  if (due) publish(controller_.step(now_ns), now_ns);
  schedule_deadline();
}

void MotionControllerNode::schedule_deadline() {
  const std::int64_t now = node::now_ns();
  const auto last = controller_.last_command_ns();
  std::int64_t deadline = last ? *last + period_ns_ - kMinimumRateSlackNs : now;
  const auto stale_at = controller_.stale_at_ns();
  if (stale_at && last_mode_ != Mode::kStale && stale_at != stale_handled_)
    deadline = std::min(deadline, *stale_at);
  // The controller's times are the wall clock, the runner's timers monotonic: converted by the
  // difference, and never further than one command period ahead, so a step of the wall clock
  // cannot silence the minimum rate for longer than that.
  const std::int64_t delay = std::clamp<std::int64_t>(deadline - now, 0, period_ns_);
  runner_.wake_at(deadline_timer_, node::monotonic_ns() + delay);
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
    schedule_deadline();
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
    schedule_deadline();
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
