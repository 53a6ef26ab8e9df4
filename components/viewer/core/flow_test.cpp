#include "viewer/core/flow.hpp"

#include <gtest/gtest.h>

namespace stereoball::viewer {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(RateLimiter, PassesAtMostTheRateAndKeepsARateSourceAtTheLimit) {
  // Given a 10 Hz limit and events every 33 ms (30 Hz)
  RateLimiter limiter(10);
  int passed = 0;
  for (int i = 0; i < 90; ++i) passed += limiter.admit(i * 33 * kMs);
  // Then about a third pass (3 s of events at 10 Hz, plus the burst of two the limiter allows
  // at the start)
  EXPECT_GE(passed, 28);
  EXPECT_LE(passed, 32);
  // And a source exactly at the limit, with jitter, loses nothing
  RateLimiter exact(10);
  int exact_passed = 0;
  for (int i = 0; i < 50; ++i) exact_passed += exact.admit(i * 100 * kMs + (i % 2 ? 3 : -3) * kMs);
  EXPECT_EQ(exact_passed, 50);
}

TEST(RateLimiter, SaysHowLongToWaitInsteadOfLosingAnEarlyEvent) {
  // Given a 30 Hz limit that passed two events back to back (its whole burst)
  RateLimiter limiter(30);
  EXPECT_EQ(limiter.wait_ns(0), 0);
  ASSERT_TRUE(limiter.admit(0));
  ASSERT_TRUE(limiter.admit(1 * kMs));
  // When the next comes early, it is told to wait, not dropped
  const int64_t wait = limiter.wait_ns(10 * kMs);
  EXPECT_GT(wait, 0);
  EXPECT_FALSE(limiter.admit(10 * kMs));
  // And after that wait it passes
  EXPECT_EQ(limiter.wait_ns(10 * kMs + wait), 0);
  EXPECT_TRUE(limiter.admit(10 * kMs + wait));
}

TEST(RateLimiter, BurstyJitterAtTheRateLosesNothingButTheAverageStaysBounded) {
  // Given a 30 Hz limit and a 30 Hz source whose frames come in pairs (late, then early)
  RateLimiter limiter(30);
  int passed = 0;
  for (int i = 0; i < 60; ++i) passed += limiter.admit(i / 2 * 66'667'000 + (i % 2) * 2 * kMs);
  // Then every frame passes
  EXPECT_EQ(passed, 60);
  // And a 120 Hz source is held to about 30 per second
  RateLimiter fast(30);
  int fast_passed = 0;
  for (int i = 0; i < 240; ++i) fast_passed += fast.admit(i * 8'333'333);
  EXPECT_GE(fast_passed, 59);
  EXPECT_LE(fast_passed, 63);
}

TEST(RateLimiter, ZeroRatePassesEverything) {
  RateLimiter limiter(0);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(limiter.admit(5));
}

TEST(ClientFlow, BrowserGetsAtMostFramesInFlightUntilItAcks) {
  // Given a browser that acknowledges drawn frames, two frames may be in flight
  FlowParams p;
  p.max_frames_in_flight = 2;
  ClientFlow flow(p, /*acks=*/true);
  EXPECT_EQ(flow.offer_image(0, 0), Decision::kSend);
  EXPECT_EQ(flow.offer_image(0, 1), Decision::kSend);
  // When a third arrives before any ack, it is dropped, not queued
  EXPECT_EQ(flow.offer_image(0, 2), Decision::kDrop);
  EXPECT_EQ(flow.dropped_images(), 1u);
  // Then one ack frees one slot
  flow.on_ack();
  EXPECT_EQ(flow.offer_image(0, 3), Decision::kSend);
  EXPECT_EQ(flow.sent_images(), 3u);
}

TEST(ClientFlow, ReadyForImageSaysWhatTheNextOfferWouldDo) {
  // Given a page with one frame in flight of at most two
  FlowParams p;
  p.max_frames_in_flight = 2;
  ClientFlow page(p, /*acks=*/true);
  ASSERT_EQ(page.offer_image(0, 0), Decision::kSend);
  EXPECT_TRUE(page.ready_for_image(0));
  // When the second is in flight, it is not ready (nothing would be sent), until an ack
  ASSERT_EQ(page.offer_image(0, 1), Decision::kSend);
  EXPECT_FALSE(page.ready_for_image(0));
  page.on_ack();
  EXPECT_TRUE(page.ready_for_image(0));
  // And a backlog over the drop limit makes any client not ready
  ClientFlow foxglove(p, /*acks=*/false);
  EXPECT_TRUE(foxglove.ready_for_image(p.drop_images_above_bytes));
  EXPECT_FALSE(foxglove.ready_for_image(p.drop_images_above_bytes + 1));
}

TEST(ClientFlow, PageGetsTheNextSceneOnlyAfterAcknowledgingTheLast) {
  ClientFlow page(FlowParams{}, /*acks=*/true);
  EXPECT_EQ(page.offer_scene(0, 0), Decision::kSend);
  EXPECT_EQ(page.offer_scene(0, 1), Decision::kDrop);
  page.on_scene_ack();
  EXPECT_EQ(page.offer_scene(0, 2), Decision::kSend);
  // A client without acks gets every scene while it keeps up
  ClientFlow foxglove(FlowParams{}, /*acks=*/false);
  EXPECT_EQ(foxglove.offer_scene(0, 0), Decision::kSend);
  EXPECT_EQ(foxglove.offer_scene(0, 1), Decision::kSend);
}

TEST(ClientFlow, ClientWithoutAcksIsThrottledByQueuedBytes) {
  FlowParams p;
  ClientFlow flow(p, /*acks=*/false);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(flow.offer_image(0, i), Decision::kSend);
  EXPECT_EQ(flow.offer_image(p.drop_images_above_bytes + 1, 20), Decision::kDrop);
  // Small messages still go while images are being dropped
  EXPECT_EQ(flow.offer_message(p.drop_images_above_bytes + 1, 21), Decision::kSend);
}

TEST(ClientFlow, ClientThatNeverReadsIsCutOffAfterTheStallTimeout) {
  FlowParams p;
  p.stall_timeout_ns = 1000 * kMs;
  ClientFlow flow(p, false);
  const uint64_t backlog = p.drop_images_above_bytes + 10;
  EXPECT_EQ(flow.offer_image(backlog, 0), Decision::kDrop);
  EXPECT_EQ(flow.offer_image(backlog, 999 * kMs), Decision::kDrop);
  EXPECT_EQ(flow.offer_image(backlog, 1000 * kMs), Decision::kDisconnect);
}

TEST(ClientFlow, DrainingResetsTheStallClockAndAHugeBacklogCutsAtOnce) {
  FlowParams p;
  p.stall_timeout_ns = 1000 * kMs;
  ClientFlow flow(p, false);
  const uint64_t backlog = p.drop_images_above_bytes + 10;
  EXPECT_EQ(flow.offer_image(backlog, 0), Decision::kDrop);
  EXPECT_EQ(flow.offer_message(0, 900 * kMs), Decision::kSend);  // it read everything
  EXPECT_EQ(flow.offer_image(backlog, 1500 * kMs), Decision::kDrop);
  EXPECT_EQ(flow.offer_message(p.disconnect_above_bytes + 1, 1501 * kMs), Decision::kDisconnect);
}

TEST(FlowParams, ValidateNamesTheBadField) {
  FlowParams p;
  EXPECT_TRUE(p.validate().ok());
  p.disconnect_above_bytes = p.drop_images_above_bytes;
  ASSERT_FALSE(p.validate().ok());
  EXPECT_NE(p.validate().error().find("disconnect_above_bytes"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::viewer
