#include "camera_server/core/frame_builder.hpp"

#include "camera_server/core/format_negotiation.hpp"
#include "camera_server/core/pixel_convert.hpp"
#include "stereo/image/yuyv_convert.hpp"

namespace stereoball::camera_server {
namespace {

stereo::EyeView raw_view(const RawImage& raw, int64_t stamp_ns) {
  return stereo::EyeView{stamp_ns,       raw.width_px,     raw.height_px,
                         raw.step_bytes, raw.bytes.data(), raw.bytes.size()};
}

}  // namespace

Status FrameBuilderParams::validate() const {
  if (publish_encoding != "bgr8" && publish_encoding != "native") {
    return Error{"publish_encoding must be \"bgr8\" or \"native\", got \"" + publish_encoding +
                 "\""};
  }
  return {};
}

FrameBuilder::FrameBuilder(const FrameBuilderParams& params) : params_(params) {}

Status FrameBuilder::convert(const RawImage& raw, cv::Mat& out) const {
  if (raw.fourcc == kFourccYuyv) {
    return stereo::yuyv_to_bgr(raw.bytes, static_cast<int>(raw.width_px),
                               static_cast<int>(raw.height_px), static_cast<int>(raw.step_bytes),
                               out);
  }
  if (raw.fourcc == kFourccMjpeg) {
    return mjpeg_to_bgr(raw.bytes, static_cast<int>(raw.width_px), static_cast<int>(raw.height_px),
                        out);
  }
  return fail("cannot convert pixel format " + fourcc_text(raw.fourcc) + " to bgr8");
}

Result<stereo::FrameView> FrameBuilder::step(const RawStereoPair& pair) {
  if (pair.left.fourcc != pair.right.fourcc) {
    return fail("left camera delivers " + fourcc_text(pair.left.fourcc) + " but right " +
                fourcc_text(pair.right.fourcc) + "; both must use the same pixel format");
  }
  stereo::FrameView v;
  v.seq = pair.seq;
  v.stamp_ns = pair.stamp_ns;
  if (params_.publish_encoding == "native") {
    if (pair.left.fourcc != kFourccYuyv && pair.left.fourcc != kFourccMjpeg) {
      return fail("pixel format " + fourcc_text(pair.left.fourcc) +
                  " has no stereo/frame encoding");
    }
    v.encoding = pair.left.fourcc == kFourccYuyv ? "yuyv" : "jpeg";
    v.left = raw_view(pair.left, pair.left_stamp_ns);
    v.right = raw_view(pair.right, pair.right_stamp_ns);
    if (pair.left.fourcc == kFourccMjpeg) v.left.step_bytes = v.right.step_bytes = 0;
    return v;
  }
  if (auto s = convert(pair.left, bgr_[0]); !s.ok()) return Error{"left camera: " + s.error()};
  if (auto s = convert(pair.right, bgr_[1]); !s.ok()) return Error{"right camera: " + s.error()};
  v.encoding = "bgr8";
  v.left = stereo::eye_view(bgr_[0], pair.left_stamp_ns);
  v.right = stereo::eye_view(bgr_[1], pair.right_stamp_ns);
  return v;
}

}  // namespace stereoball::camera_server
