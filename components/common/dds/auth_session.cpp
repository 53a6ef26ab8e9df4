#include "common/dds/auth_session.hpp"

#include <dds/ddsi/ddsi_cdrstream.h>
#include <sodium.h>
#include <sys/stat.h>

#include <cstring>
#include <stdexcept>

#include "common/auth/key_file.hpp"
#include "common/util/clock.hpp"
#include "common/util/log.hpp"

namespace stereoball::dds {
namespace {

constexpr int64_t kReloadCheckPeriodNs = 1'000'000'000;
// After a reload names a new signing key, the previous one signs this much longer: every
// process sharing the file re-reads it within one check period; the second is a margin for a
// loaded host.
constexpr int64_t kSigningSwitchDelayNs = 2 * kReloadCheckPeriodNs;
constexpr uint32_t kXcdr1 = 1;

using util::wall_ns;
int64_t mono_ns() {
  return util::monotonic_ns();
}

int64_t mtime_ns(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return -1;
  return static_cast<int64_t>(st.st_mtim.tv_sec) * 1'000'000'000 + st.st_mtim.tv_nsec;
}

auth::Mac mac_of(const stereoball_msg_AuthTag& tag) {
  auth::Mac mac;
  std::memcpy(mac.data(), tag.mac, mac.size());
  return mac;
}

}  // namespace

std::vector<uint8_t> canonical_encoding(const dds_topic_descriptor_t* desc, const void* sample) {
  dds_ostreamLE_t os;
  dds_ostreamLE_init(&os, 0, kXcdr1);
  dds_stream_writeLE(&os, static_cast<const char*>(sample), desc->m_ops);
  std::vector<uint8_t> out(os.x.m_buffer, os.x.m_buffer + os.x.m_index);
  dds_ostreamLE_fini(&os);
  return out;
}

AuthSession::AuthSession(std::string key_file, const auth::WindowParams& window)
    : key_file_(std::move(key_file)), window_(window), schedule_(kSigningSwitchDelayNs) {
  if (auto e = window_.validate(); !e) throw std::runtime_error("replay window: " + e.error());
  if (key_file_.empty()) return;
  auto ring = auth::load_key_file(key_file_);
  if (!ring) throw std::runtime_error(ring.error());
  ring_ = std::move(*ring);
  schedule_.on_ring(ring_, wall_ns());
  file_mtime_ns_ = mtime_ns(key_file_);
  next_check_mono_ns_ = mono_ns() + kReloadCheckPeriodNs;
}

void AuthSession::reload_if_changed() {
  // Key rotation without a restart: the file is replaced atomically (rename), so a change of
  // its time stamp means a complete new ring. A bad new file keeps the old keys working.
  const int64_t mono = mono_ns();
  if (mono < next_check_mono_ns_) return;
  next_check_mono_ns_ = mono + kReloadCheckPeriodNs;
  const int64_t mtime = mtime_ns(key_file_);
  if (mtime == file_mtime_ns_) return;
  auto ring = auth::load_key_file(key_file_);
  if (!ring) {
    log::error("keeping the previous deployment keys: ", ring.error());
    ++counters_["auth_key_reload_failed"];
    return;
  }
  ring_ = std::move(*ring);
  schedule_.on_ring(ring_, wall_ns());
  file_mtime_ns_ = mtime;
  ++counters_["auth_key_reloads"];
  log::info("deployment keys reloaded from ", key_file_, " (signing key ", ring_.signing()->id,
            ")");
}

uint32_t AuthSession::signing_key_id() {
  if (!keyed()) return 0;
  std::lock_guard lock(mutex_);
  reload_if_changed();
  return schedule_.signing(ring_, wall_ns())->id;
}

uint32_t AuthSession::signing_key_fingerprint() {
  if (!keyed()) return 0;
  std::lock_guard lock(mutex_);
  reload_if_changed();
  // The hash `stereoball keys show` prints (key_file.cpp); 4 of its bytes reveal nothing.
  const auth::Key& key = schedule_.signing(ring_, wall_ns())->key;
  unsigned char hash[crypto_generichash_BYTES];
  crypto_generichash(hash, sizeof hash, key.data(), key.size(), nullptr, 0);
  return (uint32_t{hash[0]} << 24) | (uint32_t{hash[1]} << 16) | (uint32_t{hash[2]} << 8) |
         uint32_t{hash[3]};
}

void AuthSession::sign(const topics::TopicSpec& spec, auth::LinkClock& clock,
                       stereoball_msg_AuthTag& tag, const void* sample) {
  std::memset(&tag, 0, sizeof tag);
  std::lock_guard lock(mutex_);
  // Keyless samples still carry link and stamp (no key, no MAC), so latched states keep their
  // newest-wins order and relays do not echo each other.
  tag.link_id = clock.link_id();
  tag.stamp_ns = clock.next(wall_ns());
  if (!keyed()) return;
  reload_if_changed();
  const auth::KeyEntry* key = schedule_.signing(ring_, wall_ns());
  tag.key_id = key->id;
  const auth::Mac mac =
      auth::compute_mac(key->key, spec.name, canonical_encoding(spec.descriptor, sample));
  std::memcpy(tag.mac, mac.data(), mac.size());
}

auth::Verdict AuthSession::verify(const topics::TopicSpec& spec, auth::ReplayGuard& guard,
                                  stereoball_msg_AuthTag& tag, void* sample) {
  if (!keyed()) return verify_keyless(spec, guard, tag);
  const auth::Mac mac = mac_of(tag);
  std::memset(tag.mac, 0, sizeof tag.mac);
  const std::vector<uint8_t> canonical = canonical_encoding(spec.descriptor, sample);
  std::memcpy(tag.mac, mac.data(), mac.size());
  std::lock_guard lock(mutex_);
  reload_if_changed();
  const auth::Verdict verdict = auth::verify(ring_, guard, spec.name, canonical, tag.key_id,
                                             tag.link_id, tag.stamp_ns, mac, wall_ns());
  ++counters_["auth_" + std::string(auth::to_string(verdict)) + ":" + std::string(spec.name)];
  const bool rejected = verdict != auth::Verdict::kAccepted && verdict != auth::Verdict::kDuplicate;
  if (rejected && reject_log_.allow(mono_ns())) {
    log::warn("dropped a ", auth::to_string(verdict), " ", spec.name, " sample (link ", tag.link_id,
              ", ", reject_log_.suppressed(), " rejections not logged before)");
  }
  return verdict;
}

auth::Verdict AuthSession::verify_keyless(const topics::TopicSpec& spec, auth::ReplayGuard& guard,
                                          const stereoball_msg_AuthTag& tag) {
  if (spec.auth != topics::Auth::kLatest) return auth::Verdict::kAccepted;
  std::lock_guard lock(mutex_);
  const auth::Verdict verdict = guard.check(tag.link_id, tag.stamp_ns, wall_ns());
  if (verdict == auth::Verdict::kAccepted) guard.accept(tag.link_id, tag.stamp_ns);
  ++counters_["auth_" + std::string(auth::to_string(verdict)) + ":" + std::string(spec.name)];
  return verdict;
}

auth::ReplayGuard AuthSession::make_guard(const topics::TopicSpec& spec) const {
  return auth::ReplayGuard(
      spec.auth == topics::Auth::kLatest ? auth::ReplayRule::kLatest : auth::ReplayRule::kStream,
      window_);
}

std::map<std::string, uint64_t> AuthSession::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

}  // namespace stereoball::dds
