#pragma once
// AuthSession: the process's deployment keys applied to DDS samples. Every DataWriter of an
// authenticated topic (topics::Auth) signs through it and every DataReader checks through it,
// so nodes never handle tags themselves. Without a key file the session is keyless: nothing
// is signed or checked, and the participant is confined to loopback (participant.hpp).

#include <dds/dds.h>

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/auth/auth.hpp"
#include "common/util/log.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::dds {

/// Samples of a type with an `auth` member (stereoball_msg_AuthTag) are authenticated.
template <typename T>
concept Authenticated = requires(T t) {
  t.auth.mac[0];
};

/// Little-endian XCDR1 encoding of sample (every field), the bytes the MAC covers.
std::vector<uint8_t> canonical_encoding(const dds_topic_descriptor_t* desc, const void* sample);

class AuthSession {
 public:
  /// Keys from key_file (re-read when the file changes); "" = keyless. Throws
  /// std::runtime_error naming the file and the problem when it cannot be used.
  explicit AuthSession(std::string key_file, const auth::WindowParams& window = {});

  bool keyed() const { return !key_file_.empty(); }
  const std::string& key_file() const { return key_file_; }

  /// Fills tag (key id, link, stamp, MAC) for sample, which contains tag. Keyless: link and
  /// stamp only (key id 0, no MAC).
  void sign(const topics::TopicSpec& spec, auth::LinkClock& clock, stereoball_msg_AuthTag& tag,
            const void* sample);
  /// Checks sample (which contains tag; tag is restored afterwards) and counts the verdict.
  /// Keyless: nothing is checked but the newest-wins order of latched topics.
  auth::Verdict verify(const topics::TopicSpec& spec, auth::ReplayGuard& guard,
                       stereoball_msg_AuthTag& tag, void* sample);
  /// A replay guard for one reader of spec's topic.
  auth::ReplayGuard make_guard(const topics::TopicSpec& spec) const;

  /// Verdict counts by "auth_<verdict>:<topic>" (for health/status).
  std::map<std::string, uint64_t> counters() const;
  /// Key id that signs now (0 keyless).
  uint32_t signing_key_id();
  /// First 4 bytes (big-endian) of the `stereoball keys show` fingerprint of the signing key,
  /// so hosts can compare keys whose ids agree by chance (0 keyless).
  uint32_t signing_key_fingerprint();

 private:
  void reload_if_changed();  // caller holds mutex_
  auth::Verdict verify_keyless(const topics::TopicSpec& spec, auth::ReplayGuard& guard,
                               const stereoball_msg_AuthTag& tag);

  std::string key_file_;
  auth::WindowParams window_;
  mutable std::mutex mutex_;
  auth::Keyring ring_;
  auth::SigningSchedule schedule_;
  int64_t file_mtime_ns_ = 0;
  int64_t next_check_mono_ns_ = 0;
  std::map<std::string, uint64_t> counters_;
  log::Throttle reject_log_{1'000'000'000};
};

}  // namespace stereoball::dds
