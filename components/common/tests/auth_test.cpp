// Message authentication core: MAC, key ring, replay window edges (pure, no DDS).
#include "common/auth/auth.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "common/auth/key_file.hpp"

namespace sa = stereoball::auth;

namespace {

constexpr int64_t kNow = 1'800'000'000'000'000'000;  // a wall-clock time, ns
constexpr int64_t kSecond = 1'000'000'000;

sa::Keyring ring_with(uint32_t id, const sa::Key& key) {
  sa::Keyring ring;
  ring.keys.push_back({id, key, true, INT64_MAX});
  return ring;
}

std::vector<uint8_t> bytes(std::initializer_list<uint8_t> b) {
  return b;
}

}  // namespace

TEST(AuthMac, DependsOnKeyTopicAndEveryByte) {
  // Given a key and a message
  const sa::Key key = sa::random_key();
  const auto message = bytes({1, 2, 3, 4, 5});
  const sa::Mac mac = sa::compute_mac(key, "cmd/velocity", message);
  // Then the same inputs give the same MAC, and any change gives another
  EXPECT_TRUE(sa::same_mac(mac, sa::compute_mac(key, "cmd/velocity", message)));
  EXPECT_FALSE(sa::same_mac(mac, sa::compute_mac(key, "cmd/estop", message)));
  EXPECT_FALSE(sa::same_mac(mac, sa::compute_mac(sa::random_key(), "cmd/velocity", message)));
  for (size_t i = 0; i < message.size(); ++i) {
    auto flipped = message;
    flipped[i] ^= 0x01;
    EXPECT_FALSE(sa::same_mac(mac, sa::compute_mac(key, "cmd/velocity", flipped))) << i;
  }
  // The topic/body boundary is part of the input
  EXPECT_FALSE(sa::same_mac(sa::compute_mac(key, "ab", bytes({'c'})),
                            sa::compute_mac(key, "a", bytes({'b', 'c'}))));
}

TEST(AuthVerify, RejectsUnsignedUnknownKeyAndForgedBeforeReplay) {
  const sa::Key key = sa::random_key();
  const sa::Keyring ring = ring_with(7, key);
  sa::ReplayGuard guard(sa::ReplayRule::kStream, {});
  const auto msg = bytes({9, 9, 9});
  const sa::Mac good = sa::compute_mac(key, "t", msg);
  // Given samples of link 1 at the reader's time
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 0, 1, kNow, good, kNow), sa::Verdict::kUnsigned);
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 8, 1, kNow, good, kNow), sa::Verdict::kUnknownKey);
  sa::Mac bad = good;
  bad[31] ^= 0x80;
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 7, 1, kNow, bad, kNow), sa::Verdict::kForged);
  // A MAC made by another key under the right key id is a forgery too
  const sa::Mac other = sa::compute_mac(sa::random_key(), "t", msg);
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 7, 1, kNow, other, kNow), sa::Verdict::kForged);
  // The genuine sample is accepted once; the same again is a replay
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 7, 1, kNow, good, kNow), sa::Verdict::kAccepted);
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 7, 1, kNow, good, kNow + 1), sa::Verdict::kReplayed);
}

TEST(AuthVerify, RotatedOutKeyIsAcceptedUntilItsGraceEnds) {
  // Given a ring where key 1 was rotated out until kNow + 10 s and key 2 signs
  sa::Keyring ring;
  const sa::Key old_key = sa::random_key();
  ring.keys.push_back({1, old_key, false, kNow + 10 * kSecond});
  ring.keys.push_back({2, sa::random_key(), true, INT64_MAX});
  ASSERT_TRUE(ring.validate().ok());
  const auto msg = bytes({1});
  const sa::Mac mac = sa::compute_mac(old_key, "t", msg);
  sa::ReplayGuard guard(sa::ReplayRule::kStream, {});
  // Then key 1 is accepted just before the end of its grace and refused from then on
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 1, 1, kNow + 10 * kSecond - 1, mac,
                       kNow + 10 * kSecond - 1),
            sa::Verdict::kAccepted);
  EXPECT_EQ(sa::verify(ring, guard, "t", msg, 1, 2, kNow + 10 * kSecond, mac, kNow + 10 * kSecond),
            sa::Verdict::kUnknownKey);
}

TEST(AuthReplayWindow, StreamEdges) {
  const sa::WindowParams w{kSecond, kSecond / 2, 256};
  sa::ReplayGuard guard(sa::ReplayRule::kStream, w);
  // Freshness window: exactly max_age old is fresh, one ns more is stale
  EXPECT_EQ(guard.check(1, kNow - w.max_age_ns, kNow), sa::Verdict::kAccepted);
  EXPECT_EQ(guard.check(1, kNow - w.max_age_ns - 1, kNow), sa::Verdict::kStale);
  // Clock lead: exactly max_future ahead is taken, one ns more is not
  EXPECT_EQ(guard.check(1, kNow + w.max_future_ns, kNow), sa::Verdict::kAccepted);
  EXPECT_EQ(guard.check(1, kNow + w.max_future_ns + 1, kNow), sa::Verdict::kFuture);
  // Per link strictly increasing (MAVLink 2): equal or older is a replay, one ns newer is fine
  guard.accept(1, kNow);
  EXPECT_EQ(guard.check(1, kNow, kNow), sa::Verdict::kReplayed);
  EXPECT_EQ(guard.check(1, kNow - 1, kNow), sa::Verdict::kReplayed);
  EXPECT_EQ(guard.check(1, kNow + 1, kNow), sa::Verdict::kAccepted);
  // Another link has its own order
  EXPECT_EQ(guard.check(2, kNow - 1, kNow), sa::Verdict::kAccepted);
}

TEST(AuthReplayWindow, LatestStateWinsAtAnyAge) {
  sa::ReplayGuard guard(sa::ReplayRule::kLatest, {kSecond, kSecond / 2, 256});
  // Given a latched state published an hour ago (a late joiner receives it)
  const int64_t hour_ago = kNow - 3600 * kSecond;
  EXPECT_EQ(guard.check(1, hour_ago, kNow), sa::Verdict::kAccepted);
  guard.accept(1, hour_ago);
  // Then the same state again (a relay) is a duplicate, an older one from any link a replay,
  // a newer one from any link wins
  EXPECT_EQ(guard.check(2, hour_ago, kNow), sa::Verdict::kDuplicate);
  EXPECT_EQ(guard.check(2, hour_ago - 1, kNow), sa::Verdict::kReplayed);
  EXPECT_EQ(guard.check(3, hour_ago + 1, kNow), sa::Verdict::kAccepted);
  // And a state from too far in the future is refused (it would shadow every later one)
  EXPECT_EQ(guard.check(3, kNow + kSecond, kNow), sa::Verdict::kFuture);
}

TEST(AuthReplayWindow, ForgetsOldestLinkBeyondTheLimit) {
  sa::ReplayGuard guard(sa::ReplayRule::kStream, {kSecond, 0, 2});
  guard.accept(1, kNow - 30);
  guard.accept(2, kNow - 20);
  guard.accept(3, kNow - 10);  // link 1 is forgotten
  EXPECT_EQ(guard.check(1, kNow - 30, kNow), sa::Verdict::kAccepted);
  EXPECT_EQ(guard.check(2, kNow - 20, kNow), sa::Verdict::kReplayed);
  EXPECT_EQ(guard.check(3, kNow - 10, kNow), sa::Verdict::kReplayed);
}

TEST(AuthLinkClock, StrictlyIncreasingWhenTheClockStepsBack) {
  sa::LinkClock clock(42);
  const int64_t a = clock.next(kNow);
  const int64_t b = clock.next(kNow - kSecond);  // NTP stepped the clock back
  const int64_t c = clock.next(kNow);
  EXPECT_EQ(a, kNow);
  EXPECT_EQ(b, kNow + 1);
  EXPECT_EQ(c, kNow + 2);
  EXPECT_EQ(clock.next(kNow + kSecond), kNow + kSecond);
}

TEST(AuthKeyring, ValidateNamesTheProblem) {
  sa::Keyring ring;
  EXPECT_NE(ring.validate().error().find("exactly one signing key"), std::string::npos);
  ring.keys.push_back({0, {}, true, INT64_MAX});
  EXPECT_NE(ring.validate().error().find("reserved"), std::string::npos);
  ring.keys = {{1, {}, true, INT64_MAX}, {1, {}, false, INT64_MAX}};
  EXPECT_NE(ring.validate().error().find("twice"), std::string::npos);
}

TEST(AuthSigningSchedule, RotationSignsWithThePreviousKeyUntilReadersKnowTheNewOne) {
  // Given a signer whose ring has key 1 signing, and a reader still holding that ring
  const sa::Keyring before = ring_with(1, sa::random_key());
  sa::SigningSchedule schedule(2 * kSecond);
  schedule.on_ring(before, kNow);
  ASSERT_EQ(schedule.signing(before, kNow)->id, 1u);
  // When the signer loads the rotated ring (key 2 signs, key 1 accepted for 120 s)
  const sa::Keyring after = sa::rotate(before, kNow + kSecond, 120 * kSecond);
  ASSERT_EQ(after.signing()->id, 2u);
  schedule.on_ring(after, kNow + kSecond);
  // Then key 1 signs for the switch delay: the reader with the old ring still accepts it
  for (int64_t t : {kNow + kSecond, kNow + 2 * kSecond, kNow + 3 * kSecond - 1}) {
    const sa::KeyEntry* key = schedule.signing(after, t);
    ASSERT_NE(key, nullptr);
    EXPECT_EQ(key->id, 1u) << t;
    EXPECT_NE(before.accepted(key->id, t), nullptr) << t;
  }
  // And after it, key 2 signs (readers have re-read the file by then)
  EXPECT_EQ(schedule.signing(after, kNow + 3 * kSecond)->id, 2u);
  // And reloading the same ring again changes nothing
  schedule.on_ring(after, kNow + 4 * kSecond);
  EXPECT_EQ(schedule.signing(after, kNow + 4 * kSecond)->id, 2u);
}

TEST(AuthSigningSchedule, FirstRingSignsAtOnceAndAnExpiredPreviousKeyIsNeverUsed) {
  // Given a fresh signer: its first ring signs with its own key at once
  const sa::Keyring first = ring_with(1, sa::random_key());
  sa::SigningSchedule schedule(2 * kSecond);
  schedule.on_ring(first, kNow);
  EXPECT_EQ(schedule.signing(first, kNow)->id, 1u);
  // When a rotation gives the old key no grace at all
  const sa::Keyring no_grace = sa::rotate(first, kNow, 0);
  schedule.on_ring(no_grace, kNow);
  // Then the new key signs at once: a key the ring no longer accepts never signs
  EXPECT_EQ(schedule.signing(no_grace, kNow)->id, 2u);
}

TEST(AuthSigningSchedule, TwoRotationsInQuickSuccessionKeepTheKeyInUse) {
  // Given key 1 signing and a rotation to key 2 loaded at kNow (switch pending until kNow+2 s)
  const sa::Keyring one = ring_with(1, sa::random_key());
  sa::SigningSchedule schedule(2 * kSecond);
  schedule.on_ring(one, kNow);
  const sa::Keyring two = sa::rotate(one, kNow, 120 * kSecond);
  schedule.on_ring(two, kNow);
  // When a second rotation (key 3) is loaded before key 2 was ever used
  const sa::Keyring three = sa::rotate(two, kNow + kSecond, 120 * kSecond);
  schedule.on_ring(three, kNow + kSecond);
  // Then key 1, the key every reader has seen signing, goes on until the new delay ends
  EXPECT_EQ(schedule.signing(three, kNow + 2 * kSecond)->id, 1u);
  EXPECT_EQ(schedule.signing(three, kNow + 3 * kSecond - 1)->id, 1u);
  EXPECT_EQ(schedule.signing(three, kNow + 3 * kSecond)->id, 3u);
}
