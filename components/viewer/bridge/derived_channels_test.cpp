#include "viewer/bridge/derived_channels.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "viewer/bridge/view_msg.hpp"

namespace stereoball::viewer {
namespace {

TEST(Deriver, AnnotationsFollowTheEyeWhenItIsShownScaledDown) {
  // Given a deriver that shows eyes at most 640 wide, and a 1280x960 stereo frame
  DeriverParams p;
  p.image_rate_hz = 0;
  p.encoder.max_width_px = 640;
  Deriver deriver(p);
  std::vector<uint8_t> pixels(1280 * 960, 100);
  char encoding[] = "mono8";
  stereoball_msg_StereoFrame f{};
  f.encoding = encoding;
  for (auto* e : {&f.left, &f.right}) {
    e->width_px = 1280;
    e->height_px = 960;
    e->step_bytes = 1280;
    e->data._buffer = pixels.data();
    e->data._length = static_cast<uint32_t>(pixels.size());
  }
  ASSERT_EQ(deriver.on_frame(f, 0).size(), 2u) << deriver.last_error();
  // When a detection in the camera's pixels arrives
  stereoball_msg_BallDetection m{};
  m.status = stereoball_msg_DETECTION_FOUND;
  char reason[] = "ok";
  m.reason = reason;
  m.left = {400, 300, 40, 0.9f};
  m.right = {380, 300, 38, 0.8f};
  const auto out = deriver.on_detection(m);
  // Then it is drawn at half its coordinates on the 640 px wide eyes
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].cdr, foxglove::image_annotations(to_view(m), foxglove::Eye::kLeft, 640, 0.5));
  EXPECT_EQ(out[1].cdr, foxglove::image_annotations(to_view(m), foxglove::Eye::kRight, 640, 0.5));
  EXPECT_NE(out[0].cdr, foxglove::image_annotations(to_view(m), foxglove::Eye::kLeft, 640, 1.0));
}

}  // namespace
}  // namespace stereoball::viewer
