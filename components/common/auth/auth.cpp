#include "common/auth/auth.hpp"

#include <sodium.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "common/util/enum_names.hpp"

namespace stereoball::auth {
namespace {

// Domain separation: a MAC made for this scheme is never valid for another use of the key.
constexpr std::string_view kLabel = "stereoball-auth-v1";

void ensure_sodium() {
  // sodium_init() is idempotent and thread-safe; it fails only without an entropy source.
  static const bool ok = sodium_init() >= 0;
  if (!ok) throw std::runtime_error("libsodium could not initialise (no entropy source)");
}

void update(crypto_auth_hmacsha512256_state& state, std::string_view text) {
  // With its terminating zero, so ("ab","c") and ("a","bc") differ.
  crypto_auth_hmacsha512256_update(&state, reinterpret_cast<const unsigned char*>(text.data()),
                                   text.size());
  const unsigned char zero = 0;
  crypto_auth_hmacsha512256_update(&state, &zero, 1);
}

}  // namespace

const KeyEntry* Keyring::signing() const {
  for (const auto& k : keys) {
    if (k.signs) return &k;
  }
  return nullptr;
}

const KeyEntry* Keyring::accepted(uint32_t id, int64_t now_ns) const {
  for (const auto& k : keys) {
    if (k.id == id && id != 0 && now_ns < k.accept_until_ns) return &k;
  }
  return nullptr;
}

Status Keyring::validate() const {
  std::set<uint32_t> ids;
  int signers = 0;
  for (const auto& k : keys) {
    if (k.id == 0) return Error{"key id 0 is reserved for unsigned samples"};
    if (!ids.insert(k.id).second) return Error{"key id " + std::to_string(k.id) + " appears twice"};
    if (k.signs) ++signers;
    if (k.signs && k.accept_until_ns != INT64_MAX) {
      return Error{"the signing key " + std::to_string(k.id) + " must not expire"};
    }
  }
  if (signers != 1)
    return Error{"exactly one signing key is needed (found " + std::to_string(signers) + ")"};
  return {};
}

void SigningSchedule::on_ring(const Keyring& ring, int64_t now_ns) {
  const KeyEntry* signer = ring.signing();
  const uint32_t id = signer ? signer->id : 0;
  if (id == ring_signer_id_) return;
  if (ring_signer_id_ != 0) {
    // The key in use until now (the previous one again if a switch was still pending) goes on
    // signing for the delay: readers know it, whichever ring they hold.
    previous_id_ = now_ns < switch_ns_ ? previous_id_ : ring_signer_id_;
    switch_ns_ = now_ns > INT64_MAX - delay_ns_ ? INT64_MAX : now_ns + delay_ns_;
  }
  ring_signer_id_ = id;
}

const KeyEntry* SigningSchedule::signing(const Keyring& ring, int64_t now_ns) const {
  if (now_ns < switch_ns_ && previous_id_ != 0 && previous_id_ != ring_signer_id_) {
    if (const KeyEntry* previous = ring.accepted(previous_id_, now_ns)) return previous;
  }
  return ring.signing();
}

namespace {
constexpr util::EnumName<Verdict> kVerdictNames[] = {
    {Verdict::kAccepted, "accepted"},      {Verdict::kUnsigned, "unsigned"},
    {Verdict::kUnknownKey, "unknown_key"}, {Verdict::kForged, "forged"},
    {Verdict::kReplayed, "replayed"},      {Verdict::kStale, "stale"},
    {Verdict::kFuture, "future"},          {Verdict::kDuplicate, "duplicate"},
};
}  // namespace

std::string_view to_string(Verdict verdict) {
  return util::name_of(kVerdictNames, verdict, "?");
}

Status WindowParams::validate() const {
  if (max_age_ns <= 0) return Error{"max_age_ns must be > 0"};
  if (max_future_ns < 0) return Error{"max_future_ns must be >= 0"};
  if (max_links == 0) return Error{"max_links must be > 0"};
  return {};
}

ReplayGuard::ReplayGuard(ReplayRule rule, const WindowParams& params)
    : rule_(rule), params_(params) {}

Verdict ReplayGuard::check(uint64_t link_id, int64_t stamp_ns, int64_t now_ns) const {
  if (stamp_ns > now_ns + params_.max_future_ns) return Verdict::kFuture;
  if (rule_ == ReplayRule::kLatest) {
    // An equal stamp is the state already held arriving again (from a relay): harmless, but
    // not news either, so it is not delivered.
    if (stamp_ns == newest_ns_) return Verdict::kDuplicate;
    return stamp_ns < newest_ns_ ? Verdict::kReplayed : Verdict::kAccepted;
  }
  const auto it = last_stamp_ns_.find(link_id);
  if (it != last_stamp_ns_.end() && stamp_ns <= it->second) return Verdict::kReplayed;
  if (stamp_ns < now_ns - params_.max_age_ns) return Verdict::kStale;
  return Verdict::kAccepted;
}

void ReplayGuard::accept(uint64_t link_id, int64_t stamp_ns) {
  newest_ns_ = std::max(newest_ns_, stamp_ns);
  if (rule_ == ReplayRule::kLatest) return;
  last_stamp_ns_[link_id] = stamp_ns;
  if (last_stamp_ns_.size() <= params_.max_links) return;
  // Forget the link heard from longest ago: its old samples are stale by now or soon, so
  // the freshness window still bounds what a replay of it could achieve.
  auto oldest = std::min_element(last_stamp_ns_.begin(), last_stamp_ns_.end(),
                                 [](const auto& a, const auto& b) { return a.second < b.second; });
  last_stamp_ns_.erase(oldest);
}

int64_t LinkClock::next(int64_t now_ns) {
  last_ns_ = std::max(now_ns, last_ns_ == INT64_MIN ? now_ns : last_ns_ + 1);
  return last_ns_;
}

Mac compute_mac(const Key& key, std::string_view topic, std::span<const uint8_t> canonical) {
  ensure_sodium();
  crypto_auth_hmacsha512256_state state;
  crypto_auth_hmacsha512256_init(&state, key.data(), key.size());
  update(state, kLabel);
  update(state, topic);
  crypto_auth_hmacsha512256_update(&state, canonical.data(), canonical.size());
  Mac mac;
  crypto_auth_hmacsha512256_final(&state, mac.data());
  sodium_memzero(&state, sizeof state);
  return mac;
}

bool same_mac(const Mac& a, const Mac& b) {
  return sodium_memcmp(a.data(), b.data(), a.size()) == 0;
}

Verdict verify(const Keyring& ring, ReplayGuard& guard, std::string_view topic,
               std::span<const uint8_t> canonical, uint32_t key_id, uint64_t link_id,
               int64_t stamp_ns, const Mac& mac, int64_t now_ns) {
  if (key_id == 0) return Verdict::kUnsigned;
  const KeyEntry* key = ring.accepted(key_id, now_ns);
  if (!key) return Verdict::kUnknownKey;
  // MAC before the replay rule, so a forgery is always counted as one.
  if (!same_mac(compute_mac(key->key, topic, canonical), mac)) return Verdict::kForged;
  const Verdict replay = guard.check(link_id, stamp_ns, now_ns);
  if (replay == Verdict::kAccepted) guard.accept(link_id, stamp_ns);
  return replay;
}

Key random_key() {
  ensure_sodium();
  Key key;
  randombytes_buf(key.data(), key.size());
  return key;
}

uint64_t random_link_id() {
  ensure_sodium();
  uint64_t id = 0;
  while (id == 0) randombytes_buf(&id, sizeof id);
  return id;
}

}  // namespace stereoball::auth
