#pragma once
// DomainParticipant: the process's membership of a DDS domain, with the
// publisher and subscriber (in the chosen partition) every writer and reader uses.

#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "common/dds/entity.hpp"

namespace stereoball::dds {

/// Domain id and partition a process joins.
struct ParticipantOptions {
  ParticipantOptions() = default;
  // A constructor, not aggregate initialisation: {domain, partition} stays valid (and free of
  // missing-initializer warnings) as members are added.
  ParticipantOptions(int domain,
                     std::string partition_name = {},  // NOLINT(google-explicit-constructor)
                     std::optional<std::string> key = std::nullopt)
      : domain_id(domain), partition(std::move(partition_name)), key_file(std::move(key)) {}

  int domain_id = 0;      ///< 0..232
  std::string partition;  ///< "" = default partition
  /// Deployment key file; nullopt = $STEREOBALL_KEY_FILE; "" = keyless (loopback only).
  std::optional<std::string> key_file;
};

class AuthSession;

class DomainParticipant {
 public:
  explicit DomainParticipant(const ParticipantOptions& options);
  EntityHandle handle() const { return participant_.handle(); }
  EntityHandle publisher() const { return publisher_.handle(); }
  EntityHandle subscriber() const { return subscriber_.handle(); }
  const ParticipantOptions& options() const { return options_; }
  /// Signing and checking of authenticated topics (shared by every reader and writer).
  AuthSession& auth() const { return *auth_; }
  /// The built-in Cyclone configuration (XML) this participant runs under instead of
  /// CYCLONEDDS_URI: keyless_cyclone_config() without a deployment key, "" with one.
  std::string built_in_config() const;

 private:
  ParticipantOptions options_;
  std::shared_ptr<AuthSession> auth_;
  std::shared_ptr<Entity> loopback_domain_;  // keyless only; outlives participant_
  Entity participant_;
  Entity publisher_;
  Entity subscriber_;
};

/// The key file a participant uses: explicit, else $STEREOBALL_KEY_FILE, else "" (keyless).
std::string resolve_key_file(const std::optional<std::string>& key_file);

/// The Cyclone configuration (XML) of a keyless participant's domain: loopback only, unicast
/// discovery, buffers sized for stereo frames (as config/cyclonedds/loopback.xml). For tools
/// that run another DDS program (ddsperf) under the same configuration as ours.
const char* keyless_cyclone_config();

/// Domain id from the STEREOBALL_DOMAIN environment variable, or fallback.
int domain_from_env(int fallback = 0);

}  // namespace stereoball::dds
