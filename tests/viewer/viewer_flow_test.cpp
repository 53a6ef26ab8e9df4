// How `stereoball view` spends its CPU on images, asserted through its own counters (/stats),
// never through timing: each frame is JPEG-encoded once whatever the number of clients, and
// nothing is encoded while no client could take an image.

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "viewer_test_support.hpp"

namespace stereoball::testing {
namespace {

using namespace std::chrono_literals;

TEST(ViewerFlow, EachFrameIsEncodedOnceForAllClients) {
  // Given a viewer, frames at 10 Hz (below its 30 Hz image rate) and three pages that ack
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition);
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  KnownScene scene(partition, 10);
  std::vector<std::unique_ptr<WsClient>> pages;
  for (int i = 0; i < 3; ++i) {
    pages.push_back(std::make_unique<WsClient>(viewer.port, WsClient::Kind::kPage, /*acks=*/true));
    ASSERT_TRUE(pages.back()->connected());
  }
  ASSERT_TRUE(eventually([&] { return pages.back()->images() >= 3; }, 60s))
      << http_get(viewer.port, "/stats");
  // When images flow to all three for a while
  const long encoded0 = stats_counter(viewer.port, "pairs_encoded");
  const long sent0 = stats_counter(viewer.port, "images_sent");
  const uint64_t published0 = scene.frames_published();
  ASSERT_TRUE(
      eventually([&] { return stats_counter(viewer.port, "pairs_encoded") >= encoded0 + 10; }, 60s))
      << http_get(viewer.port, "/stats");
  const long encoded = stats_counter(viewer.port, "pairs_encoded") - encoded0;
  const long sent = stats_counter(viewer.port, "images_sent") - sent0;
  const uint64_t published = scene.frames_published() - published0;
  // Then no frame was encoded more than once (at most one per published frame, plus the one
  // in the encoder when counting started) and each encoded pair went to several clients
  EXPECT_LE(encoded, static_cast<long>(published) + 1) << http_get(viewer.port, "/stats");
  EXPECT_GT(sent, 2 * encoded) << http_get(viewer.port, "/stats");
}

TEST(ViewerFlow, NothingIsEncodedWhileNoClientCanTakeAnImage) {
  // Given a viewer, frames at 10 Hz and one page that reads but never acknowledges a pair
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition);
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  KnownScene scene(partition, 10);
  WsClient page(viewer.port, WsClient::Kind::kPage, /*acks=*/false);
  ASSERT_TRUE(page.connected());
  // When it holds the two pairs a page may have in flight
  ASSERT_TRUE(eventually([&] { return page.images() >= 2; }, 60s))
      << http_get(viewer.port, "/stats");
  const long encoded = stats_counter(viewer.port, "pairs_encoded");
  const uint64_t published = scene.frames_published();
  // Then frames keep coming but are skipped, not encoded
  ASSERT_TRUE(eventually([&] { return scene.frames_published() >= published + 15; }, 60s));
  EXPECT_LE(stats_counter(viewer.port, "pairs_encoded"), encoded + 1)
      << http_get(viewer.port, "/stats");
  EXPECT_EQ(page.images(), 2u);
  // And one acknowledgement frees a slot: encoding resumes
  page.ack();
  EXPECT_TRUE(eventually([&] { return page.images() >= 3; }, 30s))
      << http_get(viewer.port, "/stats");
  EXPECT_GT(stats_counter(viewer.port, "pairs_encoded"), encoded);
}

TEST(ViewerFlow, PairsCarryTheSizeTheDetectionsReferTo) {
  // Given 320x240 eyes and a viewer that shows them at most 160 px wide
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition, {"--max-width", "160"});
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  KnownScene scene(partition, 10);
  WsClient page(viewer.port, WsClient::Kind::kPage);
  ASSERT_TRUE(page.connected());
  // When pairs arrive
  ASSERT_TRUE(eventually([&] { return page.images() >= 2; }, 60s))
      << http_get(viewer.port, "/stats");
  // Then each says the eyes' own size (the page scales the circles by shown / source width)
  // and when the viewer took and encoded it, after the capture
  const auto h = page.last_pair();
  ASSERT_TRUE(h);
  EXPECT_EQ(h->source_width_px, 320u);
  EXPECT_EQ(h->source_height_px, 240u);
  EXPECT_EQ(h->capture_ms, scene.values().capture_stamp_ns / 1e6);
  EXPECT_GE(h->encoded_ms, h->received_ms);
  EXPECT_GT(h->received_ms, 0);
}

TEST(ViewerFlow, APublishersPreviewIsShownAndMadeOnlyWhileSomeoneWatches) {
  // Given a publisher that offers stereo/preview beside its raw frames, and a viewer
  const std::string partition = unique_partition();
  KnownScene scene(partition, 10, /*noise_frames=*/false, /*with_preview=*/true);
  auto viewer = start_viewer(partition);
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  // When no client is connected, then no preview is made (no reader asks for one)
  ASSERT_TRUE(eventually([&] { return scene.frames_published() >= 15; }, 60s));
  EXPECT_EQ(scene.previews_published(), 0u);
  EXPECT_EQ(scene.preview_readers(), 0u);
  // When a page connects
  auto page = std::make_unique<WsClient>(viewer.port, WsClient::Kind::kPage);
  ASSERT_TRUE(page->connected());
  ASSERT_TRUE(eventually([&] { return page->images() >= 5; }, 60s))
      << http_get(viewer.port, "/stats");
  // Then it is shown the publisher's previews, none encoded by the viewer, and the raw frames
  // are not sent to the viewer at all
  EXPECT_GE(stats_counter(viewer.port, "pairs_from_preview"), 5) << http_get(viewer.port, "/stats");
  EXPECT_EQ(stats_counter(viewer.port, "pairs_encoded"), 0) << http_get(viewer.port, "/stats");
  EXPECT_GT(scene.previews_published(), 0u);
  EXPECT_EQ(scene.frame_readers(), 0u);
  // And each pair still says the raw eyes' size (the detections' pixels) and the capture time
  const auto h = page->last_pair();
  ASSERT_TRUE(h);
  EXPECT_EQ(h->source_width_px, scene.values().width_px);
  EXPECT_EQ(h->source_height_px, scene.values().height_px);
  EXPECT_EQ(h->capture_ms, scene.values().capture_stamp_ns / 1e6);
  // When the page leaves, the viewer drops its preview reader and the publisher stops making
  // previews
  page.reset();
  ASSERT_TRUE(eventually([&] { return scene.preview_readers() == 0; }, 60s));
  const uint64_t previews = scene.previews_published();
  const uint64_t frames = scene.frames_published();
  ASSERT_TRUE(eventually([&] { return scene.frames_published() >= frames + 15; }, 60s));
  // (one preview may have been in the worker when the reader went)
  EXPECT_LE(scene.previews_published(), previews + 1);
}

TEST(ViewerFlow, WithNoPreviewTheRawFramesAreShownEvenWhenOneIsOffered) {
  // Given a publisher with a preview and a viewer told not to use it
  const std::string partition = unique_partition();
  KnownScene scene(partition, 10, /*noise_frames=*/false, /*with_preview=*/true);
  auto viewer = start_viewer(partition, {"--no-preview"});
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  // When a page connects
  WsClient page(viewer.port, WsClient::Kind::kPage);
  ASSERT_TRUE(page.connected());
  ASSERT_TRUE(eventually([&] { return page.images() >= 3; }, 60s))
      << http_get(viewer.port, "/stats");
  // Then the viewer encodes the raw frames and never asks for a preview
  EXPECT_GE(stats_counter(viewer.port, "pairs_encoded"), 3) << http_get(viewer.port, "/stats");
  EXPECT_EQ(stats_counter(viewer.port, "pairs_from_preview"), 0);
  EXPECT_EQ(scene.previews_published(), 0u);
}

}  // namespace
}  // namespace stereoball::testing
