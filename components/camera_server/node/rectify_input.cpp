#include "camera_server/node/rectify_input.hpp"

#include <string>

namespace stereoball::camera_server {

Result<std::array<cv::Mat, 2>> rectify_input(const stereo::FrameView& view) {
  std::array<cv::Mat, 2> eyes{stereo::image_of(view.left, view.encoding),
                              stereo::image_of(view.right, view.encoding)};
  if (eyes[0].empty() || eyes[1].empty()) {
    return Error{"cannot rectify \"" + view.encoding +
                 "\" frames (only decoded bgr8 or mono8 eyes): frame not published"};
  }
  return eyes;
}

}  // namespace stereoball::camera_server
