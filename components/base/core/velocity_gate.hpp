#pragma once
// VelocityGate: what a robot base applies, decided by the base itself: the last command while
// it is fresh and the emergency stop is released, zero otherwise. Pure (time is an argument).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "common/util/result.hpp"

namespace stereoball::base {

struct VelocityGateParams {
  int64_t command_timeout_ns = 300'000'000;  ///< a command older than this stops the base, ns
  /// Success, or the bad field and its allowed range.
  Status validate() const;
};

/// Velocity of a differential-drive base.
struct Velocity {
  double linear_mps = 0.0;     ///< forward, m/s
  double angular_radps = 0.0;  ///< yaw rate, rad/s, positive = turn left
};

enum class GateState {
  kDriving,        ///< applying the last command
  kEmergencyStop,  ///< e-stop engaged: zero, commands ignored
  kStale,          ///< the last command is older than the timeout: zero
  kNoCommand,      ///< nothing received since start or since the e-stop was released: zero
};
std::string_view to_string(GateState state);
/// The state named name (as to_string prints it), or nullopt.
std::optional<GateState> gate_state_from_string(std::string_view name);

/// The one freshness rule for a velocity command at a base: it may move the base until its own
/// stamp plus timeout_ns, and never past its receipt plus timeout_ns (a stamp ahead of the
/// base's clock buys nothing). Returns that last instant, ns since epoch (saturating for any
/// stamp, garbage included).
int64_t command_expiry_ns(int64_t stamp_ns, int64_t received_ns, int64_t timeout_ns);
/// True while now_ns <= command_expiry_ns(stamp_ns, received_ns, timeout_ns).
bool command_fresh(int64_t stamp_ns, int64_t received_ns, int64_t now_ns, int64_t timeout_ns);

struct GateOutput {
  Velocity velocity;  ///< what the base may apply now
  GateState state = GateState::kNoCommand;
};

class VelocityGate {
 public:
  explicit VelocityGate(const VelocityGateParams& params);
  /// A command stamped stamp_ns by its sender and received at received_ns (both ns since
  /// epoch; non-finite values count as zero). It drives until command_expiry_ns: a command that
  /// arrives late is stale at once. Ignored while the e-stop is engaged.
  void on_command(const Velocity& command, int64_t stamp_ns, int64_t received_ns);
  /// Engages or releases the stop. Releasing needs a new command before the base moves again.
  void set_estop(bool engaged);
  bool estop_engaged() const { return estop_; }
  /// What the base may apply at now_ns.
  GateOutput step(int64_t now_ns) const;

 private:
  VelocityGateParams params_;
  bool estop_ = false;
  std::optional<Velocity> command_;
  int64_t expiry_ns_ = 0;
};

}  // namespace stereoball::base
