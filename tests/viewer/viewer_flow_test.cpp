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
  std::vector<std::unique_ptr<PageReader>> pages;
  for (int i = 0; i < 3; ++i) {
    pages.push_back(std::make_unique<PageReader>(viewer.port, /*ack=*/true));
    ASSERT_TRUE(pages.back()->connected());
  }
  ASSERT_TRUE(eventually([&] { return pages.back()->pairs() >= 3; }, 60s))
      << http_get(viewer.port, "/stats");
  // When images flow to all three for a while
  const long encoded0 = stat(viewer.port, "pairs_encoded");
  const long sent0 = stat(viewer.port, "images_sent");
  const uint64_t published0 = scene.frames_published();
  ASSERT_TRUE(eventually([&] { return stat(viewer.port, "pairs_encoded") >= encoded0 + 10; }, 60s))
      << http_get(viewer.port, "/stats");
  const long encoded = stat(viewer.port, "pairs_encoded") - encoded0;
  const long sent = stat(viewer.port, "images_sent") - sent0;
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
  PageReader page(viewer.port, /*ack=*/false);
  ASSERT_TRUE(page.connected());
  // When it holds the two pairs a page may have in flight
  ASSERT_TRUE(eventually([&] { return page.pairs() >= 2; }, 60s))
      << http_get(viewer.port, "/stats");
  const long encoded = stat(viewer.port, "pairs_encoded");
  const uint64_t published = scene.frames_published();
  // Then frames keep coming but are skipped, not encoded
  ASSERT_TRUE(eventually([&] { return scene.frames_published() >= published + 15; }, 60s));
  EXPECT_LE(stat(viewer.port, "pairs_encoded"), encoded + 1) << http_get(viewer.port, "/stats");
  EXPECT_EQ(page.pairs(), 2u);
  // And one acknowledgement frees a slot: encoding resumes
  page.ack();
  EXPECT_TRUE(eventually([&] { return page.pairs() >= 3; }, 30s))
      << http_get(viewer.port, "/stats");
  EXPECT_GT(stat(viewer.port, "pairs_encoded"), encoded);
}

}  // namespace
}  // namespace stereoball::testing
