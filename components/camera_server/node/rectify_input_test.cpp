// camera_server's rectification takes decoded eyes only: anything else is refused by name
// instead of being published as it came.
#include "camera_server/node/rectify_input.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stereoball::camera_server {
namespace {

TEST(RectifyInput, GivenDecodedEyesWhenTakenThenBothImagesWithoutACopy) {
  // Given a bgr8 frame
  const cv::Mat left(48, 64, CV_8UC3, cv::Scalar(1, 2, 3)), right(48, 64, CV_8UC3);
  const auto view = stereo::view_of_images(left, right, 7, 1000);
  ASSERT_TRUE(view) << view.error();
  // When its eyes are taken for rectification
  const auto eyes = rectify_input(*view);
  // Then they are the frame's own pixels
  ASSERT_TRUE(eyes) << eyes.error();
  EXPECT_EQ((*eyes)[0].data, left.data);
  EXPECT_EQ((*eyes)[1].data, right.data);
  EXPECT_EQ((*eyes)[0].size(), cv::Size(64, 48));
}

TEST(RectifyInput, GivenUndecodedEyesWhenTakenThenAnErrorNamingTheEncoding) {
  // Given yuyv and jpeg frames (as a camera publishes them natively)
  const std::vector<uint8_t> bytes(64 * 48 * 2, 128);
  stereo::FrameView view;
  view.left = view.right = {0, 64, 48, 128, bytes.data(), bytes.size()};
  for (const char* encoding : {"yuyv", "jpeg"}) {
    view.encoding = encoding;
    // When their eyes are taken for rectification
    const auto eyes = rectify_input(view);
    // Then it is an error saying which frames cannot be rectified and that it is not published
    ASSERT_FALSE(eyes) << encoding;
    EXPECT_NE(eyes.error().find(std::string("\"") + encoding + "\""), std::string::npos)
        << eyes.error();
    EXPECT_NE(eyes.error().find("not published"), std::string::npos) << eyes.error();
  }
}

}  // namespace
}  // namespace stereoball::camera_server
