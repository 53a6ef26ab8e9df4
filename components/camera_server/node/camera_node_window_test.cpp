// stereoball bench camera-node's figures: CPU per frame is over the frames published.
#include "camera_server/node/camera_node_window.hpp"

#include <gtest/gtest.h>

namespace stereoball::camera_server {
namespace {

TEST(CameraNodeWindow, CpuPerFrameIsOverTheFramesPublishedNotTheNominalRate) {
  // Given a 2 s window in which a node asked for 30 Hz published only 30 frames (seq 10 -> 40)
  // and used 0.12 s of CPU
  const WindowMark start{1'000'000'000, 0.50, 10};
  const WindowMark end{3'000'000'000, 0.62, 40};
  // When the figures are taken
  const auto f = window_figures(start, end);
  // Then the CPU is spread over those 30 frames (4000 us each), not over 60 nominal ones
  ASSERT_TRUE(f) << f.error();
  EXPECT_DOUBLE_EQ(f->wall_s, 2.0);
  EXPECT_EQ(f->published, 30u);
  EXPECT_DOUBLE_EQ(f->published_hz, 15.0);
  EXPECT_NEAR(f->cpu_percent, 6.0, 1e-9);
  EXPECT_NEAR(f->cpu_us_per_frame, 4000.0, 1e-6);
}

TEST(CameraNodeWindow, NoFramePublishedOrAnEmptyWindowIsAnError) {
  // Given windows in which seq did not advance, or with no length
  const WindowMark start{1'000'000'000, 0.5, 10};
  // When their figures are taken
  const auto stalled = window_figures(start, {3'000'000'000, 0.6, 10});
  const auto empty = window_figures(start, {1'000'000'000, 0.6, 20});
  // Then each is refused with the reason
  ASSERT_FALSE(stalled);
  EXPECT_NE(stalled.error().find("no frame was published"), std::string::npos);
  ASSERT_FALSE(empty);
  EXPECT_NE(empty.error().find("empty"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::camera_server
