#pragma once
// The motion_controller process: ball/track and cmd/estop in, cmd/velocity out: one command
// per new track as soon as it arrives, at least rate_hz also when the inputs stop, and at once
// on stale input or emergency stop. Between samples it sleeps until the next of those two
// deadlines (no polling).

#include <cstddef>
#include <cstdint>
#include <optional>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/estop_holder.hpp"
#include "common/node/node_runner.hpp"
#include "motion_controller/core/motion_controller.hpp"
#include "motion_controller/node/controller_params_file.hpp"

namespace stereoball::motion_controller {

/// Wires the controller core to its topics and the minimum-rate timer on a runner.
class MotionControllerNode {
 public:
  /// Creates readers/writers on runner's participant and registers callbacks and the timer.
  MotionControllerNode(node::Runner& runner, const MotionControllerNodeParams& params);

 private:
  void on_tracks();
  void on_estop(const node::EstopState& state);
  void on_deadline(std::int64_t now_ns);
  void schedule_deadline();
  void publish(const Command& c, std::int64_t now_ns);
  void report_bad_stamp(const stereoball_msg_BallTrack& msg, StampCheck check, std::int64_t now_ns);

  node::Runner& runner_;
  MotionController controller_;
  std::int64_t period_ns_;  // longest gap between two commands (1 / rate_hz)
  dds::DataReader<stereoball_msg_BallTrack> tracks_;
  node::EstopHolder estop_;  // authenticated, held and re-published
  dds::DataWriter<stereoball_msg_VelocityCommand> commands_;
  std::uint64_t seq_ = 0;
  Mode last_mode_ = Mode::kWaiting;
  std::uint64_t bad_stamps_in_a_row_ = 0;
  StampCheck last_bad_check_ = StampCheck::kNew;
  std::size_t deadline_timer_ = 0;  // runner one-shot: next minimum-rate command or stale stop
  std::optional<std::int64_t> stale_handled_;  // stale_at_ns() the deadline already acted on
};

}  // namespace stereoball::motion_controller
