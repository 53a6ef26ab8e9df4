#include "live_frames.hpp"

namespace stereoball::calibrate_live {

Result<StationFrame> station_frame(const stereoball_msg_StereoFrame& msg,
                                   stereo::FrameDecoder& decoder) {
  StationFrame frame;
  frame.seq = msg.seq;
  frame.rectified = msg.rectified;
  frame.source = msg.source ? msg.source : "";
  frame.left_stamp_ns = msg.left.capture_stamp_ns ? msg.left.capture_stamp_ns : msg.stamp_ns;
  frame.right_stamp_ns = msg.right.capture_stamp_ns ? msg.right.capture_stamp_ns : msg.stamp_ns;
  const cv::Size size(static_cast<int>(msg.left.width_px), static_cast<int>(msg.left.height_px));
  if (auto st = decoder.decode(msg, size, frame.left, frame.right); !st)
    return Error{"frame " + std::to_string(msg.seq) + " refused: " + st.error()};
  return frame;
}

}  // namespace stereoball::calibrate_live
