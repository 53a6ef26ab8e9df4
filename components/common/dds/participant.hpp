#pragma once
// DomainParticipant: the process's membership of a DDS domain, with the
// publisher and subscriber (in the chosen partition) every writer and reader uses.

#include <string>

#include "common/dds/entity.hpp"

namespace stereoball::dds {

/// Domain id and partition a process joins.
struct ParticipantOptions {
  int domain_id = 0;      ///< 0..232
  std::string partition;  ///< "" = default partition
};

class DomainParticipant {
 public:
  explicit DomainParticipant(const ParticipantOptions& options);
  EntityHandle handle() const { return participant_.handle(); }
  EntityHandle publisher() const { return publisher_.handle(); }
  EntityHandle subscriber() const { return subscriber_.handle(); }
  const ParticipantOptions& options() const { return options_; }

 private:
  ParticipantOptions options_;
  Entity participant_;
  Entity publisher_;
  Entity subscriber_;
};

/// Domain id from the STEREOBALL_DOMAIN environment variable, or fallback.
int domain_from_env(int fallback = 0);

}  // namespace stereoball::dds
