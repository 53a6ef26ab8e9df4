#pragma once
// WaitSet with read and guard conditions: how a node sleeps until data arrives.

#include <cstdint>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/participant.hpp"

namespace stereoball::dds {

/// Triggers when its reader has any unread sample.
class ReadCondition {
 public:
  explicit ReadCondition(EntityHandle reader);
  EntityHandle handle() const { return condition_.handle(); }

 private:
  Entity condition_;
};

/// Triggered by hand (e.g. from a signal-handling thread) to wake a waitset.
class GuardCondition {
 public:
  explicit GuardCondition(const DomainParticipant& participant);
  void trigger();
  void reset();
  EntityHandle handle() const { return condition_.handle(); }

 private:
  Entity condition_;
};

class WaitSet {
 public:
  explicit WaitSet(const DomainParticipant& participant);
  /// Attaches a condition; wait() reports token when it triggers.
  void attach(EntityHandle condition, intptr_t token);
  void detach(EntityHandle condition);
  /// Waits up to timeout_ns; returns the tokens of triggered conditions (empty on timeout).
  std::vector<intptr_t> wait(int64_t timeout_ns);

 private:
  Entity waitset_;
  std::vector<EntityHandle> attached_;
};

}  // namespace stereoball::dds
