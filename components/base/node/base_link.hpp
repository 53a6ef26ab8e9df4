#pragma once
// BaseLink: what a robot base driver (the simulator's base, or a real one) uses to take its
// commands. cmd/velocity and cmd/estop arrive authenticated (common/dds); the e-stop is held
// and re-published (EstopHolder); the base's own VelocityGate decides what may be applied.

#include <cstdint>
#include <functional>
#include <string>

#include "base/core/velocity_gate.hpp"
#include "common/dds/reader.hpp"
#include "common/node/estop_holder.hpp"
#include "common/node/node_runner.hpp"

namespace stereoball::base {

/// A gated command for the driver, with what the base knows of the command behind it.
struct BaseCommand {
  GateOutput output;
  int64_t stamp_ns = 0;        ///< the command's own stamp (ns since epoch), or now for a stop
  bool from_estop = false;     ///< the e-stop changed (no command behind it)
  int64_t received_ns = 0;     ///< when the base took it, ns since epoch
  uint64_t seq = 0;            ///< the command's seq
  uint32_t key_id = 0;         ///< key id of its authentication tag (0 = unsigned)
  bool authenticated = false;  ///< its MAC was verified with the deployment key
  std::string source;          ///< the command's source field
};

class BaseLink {
 public:
  /// on_command runs on the loop thread for every accepted command and every stop.
  BaseLink(node::Runner& runner, const VelocityGateParams& params,
           std::function<void(const BaseCommand&)> on_command);
  /// What the base may apply at now_ns (for a driver's own control loop).
  GateOutput output(int64_t now_ns) const { return gate_.step(now_ns); }
  bool estop_engaged() const { return gate_.estop_engaged(); }

 private:
  void on_velocity();
  void on_estop(const node::EstopState& state);

  node::Runner& runner_;
  VelocityGate gate_;
  std::function<void(const BaseCommand&)> on_command_;
  dds::DataReader<stereoball_msg_VelocityCommand> commands_;
  node::EstopHolder estop_;
};

}  // namespace stereoball::base
