#pragma once
// Message authentication of control and configuration samples (pure: no DDS, no clock, no
// files). The scheme follows MAVLink 2 message signing: a per-link id, a signer timestamp that
// only grows per link, a keyed MAC over the message; see README.md for where it differs.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::auth {

constexpr size_t kKeyBytes = 32;  ///< crypto_auth_hmacsha512256_KEYBYTES
constexpr size_t kMacBytes = 32;  ///< crypto_auth_hmacsha512256_BYTES
using Key = std::array<uint8_t, kKeyBytes>;
using Mac = std::array<uint8_t, kMacBytes>;

/// One deployment key. Signers use the key marked signs; verifiers accept every key of the
/// ring while now < accept_until_ns (a rotated-out key keeps a grace period).
struct KeyEntry {
  uint32_t id = 0;  ///< 1.. (0 means "unsigned" on the wire)
  Key key{};
  bool signs = false;
  int64_t accept_until_ns = INT64_MAX;  ///< ns since epoch; INT64_MAX = no limit
};

/// The keys of a deployment: one that signs, others accepted (rotation grace, staged next key).
struct Keyring {
  std::vector<KeyEntry> keys;
  /// The signing key, or nullptr.
  const KeyEntry* signing() const;
  /// The key with this id if it is accepted at now_ns, or nullptr.
  const KeyEntry* accepted(uint32_t id, int64_t now_ns) const;
  /// Empty, or why the ring is unusable (no signing key, duplicate or zero ids).
  Status validate() const;
};

/// Which key a signer uses across a rotation. When a newly loaded ring names another signing
/// key, the key that signed until then keeps signing for delay_ns while the new ring still
/// accepts it (its grace), so every reader that re-reads the key file within delay_ns knows the
/// new key before the first sample signed with it: a one-shot `keys rotate` refuses nothing.
class SigningSchedule {
 public:
  explicit SigningSchedule(int64_t delay_ns) : delay_ns_(delay_ns) {}
  /// ring is in force from now_ns on (the first ring signs with its own key at once).
  void on_ring(const Keyring& ring, int64_t now_ns);
  /// The key to sign with at now_ns, from ring (the one given to on_ring last), or nullptr.
  const KeyEntry* signing(const Keyring& ring, int64_t now_ns) const;

 private:
  int64_t delay_ns_;
  uint32_t ring_signer_id_ = 0;  // the ring's own signing key (0 before the first ring)
  uint32_t previous_id_ = 0;     // signs until switch_ns_ while the ring accepts it
  int64_t switch_ns_ = INT64_MIN;
};

/// What a reader decided about one sample.
enum class Verdict {
  kAccepted,
  kUnsigned,    ///< no tag (key id 0)
  kUnknownKey,  ///< key id not in the ring, or its grace period is over
  kForged,      ///< the MAC does not match
  kReplayed,    ///< stamp not newer than the last accepted one of its link / topic
  kStale,       ///< stamp older than the freshness window
  kFuture,      ///< stamp too far ahead of the reader's clock
  kDuplicate,   ///< kLatest: the state already held, again (a relay's copy): not delivered
};
/// "accepted", "unsigned", "unknown_key", "forged", "replayed", "stale", "future", "duplicate".
std::string_view to_string(Verdict verdict);

/// How a topic is protected against replay.
enum class ReplayRule {
  kStream,  ///< per link strictly increasing stamps within a freshness window (commands...)
  kLatest,  ///< latched state: the newest authenticated stamp of the topic wins, any age
};

/// Replay window of a reader, ns.
struct WindowParams {
  int64_t max_age_ns = 1'000'000'000;   ///< kStream: older samples are stale
  int64_t max_future_ns = 500'000'000;  ///< both rules: allowed clock lead of the signer
  size_t max_links = 256;               ///< kStream: links remembered (oldest forgotten)
  Status validate() const;
};

/// Per-reader replay state. check() before accepting, accept() after the MAC verified.
class ReplayGuard {
 public:
  ReplayGuard(ReplayRule rule, const WindowParams& params);
  /// kAccepted if a sample of link stamped stamp_ns may be taken at now_ns.
  Verdict check(uint64_t link_id, int64_t stamp_ns, int64_t now_ns) const;
  /// Records an accepted sample.
  void accept(uint64_t link_id, int64_t stamp_ns);

 private:
  ReplayRule rule_;
  WindowParams params_;
  std::map<uint64_t, int64_t> last_stamp_ns_;  // kStream: per link
  int64_t newest_ns_ = INT64_MIN;              // kLatest: newest accepted
};

/// Stamps of one signing link: wall time, but strictly increasing even if the clock steps back.
class LinkClock {
 public:
  explicit LinkClock(uint64_t link_id) : link_id_(link_id) {}
  uint64_t link_id() const { return link_id_; }
  int64_t next(int64_t now_ns);

 private:
  uint64_t link_id_;
  int64_t last_ns_ = INT64_MIN;
};

/// HMAC-SHA-512-256 (libsodium crypto_auth_hmacsha512256) of a domain-separation label, the
/// topic name and the canonical encoding of the sample (its tag's mac zeroed).
Mac compute_mac(const Key& key, std::string_view topic, std::span<const uint8_t> canonical);
/// Constant-time comparison.
bool same_mac(const Mac& a, const Mac& b);

/// Full check of one sample: key, MAC, then replay (guard.accept() on success).
Verdict verify(const Keyring& ring, ReplayGuard& guard, std::string_view topic,
               std::span<const uint8_t> canonical, uint32_t key_id, uint64_t link_id,
               int64_t stamp_ns, const Mac& mac, int64_t now_ns);

/// A fresh random key / link id (libsodium randombytes).
Key random_key();
uint64_t random_link_id();

}  // namespace stereoball::auth
