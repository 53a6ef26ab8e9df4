#include "viewer/bridge/derived_channels.hpp"

#include "viewer/bridge/view_msg.hpp"

namespace stereoball::viewer {

using foxglove::DerivedChannel;
using foxglove::Eye;

Result<PairJpeg> encode_pair(EyeEncoder& encoder, const stereoball_msg_StereoFrame& frame) {
  auto left = encoder.encode(frame.left, frame.encoding);
  if (!left) return Error{"left eye: " + left.error()};
  auto right = encoder.encode(frame.right, frame.encoding);
  if (!right) return Error{"right eye: " + right.error()};
  return PairJpeg{frame.seq, frame.stamp_ns, std::move(*left), std::move(*right)};
}

Result<PairJpeg> preview_pair(EyeEncoder& encoder, const stereoball_msg_StereoPreview& preview) {
  auto left =
      encoder.encode_preview(preview.left, preview.source_width_px, preview.source_height_px);
  if (!left) return Error{"left eye: " + left.error()};
  auto right =
      encoder.encode_preview(preview.right, preview.source_width_px, preview.source_height_px);
  if (!right) return Error{"right eye: " + right.error()};
  PairJpeg pair{preview.seq, preview.stamp_ns, std::move(*left), std::move(*right)};
  pair.from_preview = true;
  return pair;
}

Status DeriverParams::validate() const {
  if (image_rate_hz < 0 || image_rate_hz > 240) return Error{"image_rate_hz must be in 0..240"};
  if (scene_rate_hz <= 0 || scene_rate_hz > 240) return Error{"scene_rate_hz must be in (0, 240]"};
  if (auto st = encoder.validate(); !st) return st;
  return scene.validate();
}

Deriver::Deriver(const DeriverParams& params)
    : params_(params),
      encoder_(params.encoder),
      scene_(params.scene),
      image_rate_(params.image_rate_hz),
      scene_rate_(params.scene_rate_hz) {}

std::vector<DerivedMessage> Deriver::on_frame(const stereoball_msg_StereoFrame& frame,
                                              int64_t now_ns) {
  if (!image_rate_.admit(now_ns)) return {};
  auto pair = encode_pair(encoder_, frame);
  if (!pair) {
    ++bad_frames_;
    last_error_ = pair.error();
    return {};
  }
  return on_pair(*pair);
}

std::vector<DerivedMessage> Deriver::on_pair(const PairJpeg& pair) {
  width_px_ = pair.left.width_px;
  // Detections come in the camera's pixels; an eye wider than max_width_px is shown smaller.
  scale_ = pair.left.source_width_px > 0
               ? static_cast<double>(pair.left.width_px) / pair.left.source_width_px
               : 1.0;
  return {{DerivedChannel::kLeftImage,
           foxglove::compressed_image(pair.capture_stamp_ns, Eye::kLeft, pair.left.bytes),
           pair.capture_stamp_ns},
          {DerivedChannel::kRightImage,
           foxglove::compressed_image(pair.capture_stamp_ns, Eye::kRight, pair.right.bytes),
           pair.capture_stamp_ns}};
}

std::vector<DerivedMessage> Deriver::on_detection(const stereoball_msg_BallDetection& m) {
  const Detection d = to_view(m);
  scene_.apply(d);
  return {{DerivedChannel::kLeftAnnotations,
           foxglove::image_annotations(d, Eye::kLeft, width_px_, scale_), d.capture_stamp_ns},
          {DerivedChannel::kRightAnnotations,
           foxglove::image_annotations(d, Eye::kRight, width_px_, scale_), d.capture_stamp_ns}};
}

std::vector<DerivedMessage> Deriver::scene_messages(int64_t stamp_ns, int64_t now_ns) {
  if (!scene_rate_.admit(now_ns)) return {};
  return {{DerivedChannel::kScene, foxglove::scene_update(scene_, stamp_ns), stamp_ns},
          {DerivedChannel::kTransforms, foxglove::frame_transforms(scene_, stamp_ns), stamp_ns}};
}

std::vector<DerivedMessage> Deriver::on_track(const stereoball_msg_BallTrack& m, int64_t now_ns) {
  scene_.apply(to_view(m));
  return scene_messages(m.capture_stamp_ns, now_ns);
}

std::vector<DerivedMessage> Deriver::on_truth(const stereoball_msg_GroundTruth& m, int64_t now_ns) {
  scene_.apply(to_view(m));
  return scene_messages(m.stamp_ns, now_ns);
}

void Deriver::on_command(const stereoball_msg_VelocityCommand& m) {
  scene_.apply(to_view(m));
}
void Deriver::on_estop(const stereoball_msg_EmergencyStop& m) {
  scene_.apply(to_view(m));
}
void Deriver::on_health(const stereoball_msg_ComponentStatus& m) {
  scene_.apply(to_view(m));
}

}  // namespace stereoball::viewer
