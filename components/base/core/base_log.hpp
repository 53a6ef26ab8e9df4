#pragma once
// The base's event log: one text line per command the base executed (its gate's output, the
// command's authentication and age), per e-stop change and per simulated frame (the robot's
// actual velocity). Written by a base driver on request (the simulator's --base-log), read by
// `stereoball bench chaos` to judge what the robot did against what it was allowed to do.
// Pure: formatting and parsing of lines only.

#include <cstdint>
#include <string>
#include <string_view>

#include "base/core/velocity_gate.hpp"
#include "common/util/result.hpp"

namespace stereoball::base {

/// What one line of the log records.
enum class BaseEventKind {
  kCommand,  ///< a cmd/velocity sample the base took, and what its gate then let through
  kEstop,    ///< the e-stop changed (or was re-announced): what the gate then let through
  kFrame,    ///< the robot's actual velocity at a simulated frame
};

/// One event of the base. Times are ns since the epoch (the base's clock).
struct BaseEvent {
  BaseEventKind kind = BaseEventKind::kCommand;
  int64_t time_ns = 0;         ///< when the base handled it (received / frame exposure)
  int64_t stamp_ns = 0;        ///< kCommand: the command's own stamp (its issuer's clock)
  uint64_t seq = 0;            ///< kCommand: the command's seq
  uint32_t key_id = 0;         ///< kCommand: key id of its authentication tag (0 = unsigned)
  bool authenticated = false;  ///< kCommand: its MAC was verified with the deployment key
  bool estop_engaged = false;  ///< the base's e-stop state after the event
  GateState state = GateState::kNoCommand;  ///< kCommand/kEstop: the gate's state after it
  double linear_mps = 0.0;     ///< applied (kCommand/kEstop: gate output; kFrame: actual), m/s
  double angular_radps = 0.0;  ///< same for the yaw rate, rad/s
  std::string source;          ///< kCommand: the command's source field (no spaces kept)
};

/// The event as one line (no newline): `cmd|estop|frame key=value ...`.
std::string format_base_event(const BaseEvent& event);
/// Parses a line written by format_base_event; an error names the bad field.
Result<BaseEvent> parse_base_event(std::string_view line);

}  // namespace stereoball::base
