#pragma once
// The derived Foxglove channels from the system's messages: one Deriver is fed every sample
// (frames, detections, tracks, commands, e-stop, ground truth, health) and returns the
// derived messages due. Used by `stereoball view` (Foxglove live) and `stereoball record`.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stereoball.h"
#include "viewer/bridge/eye_encoder.hpp"
#include "viewer/core/flow.hpp"
#include "viewer/core/foxglove_messages.hpp"
#include "viewer/core/scene.hpp"

namespace stereoball::viewer {

/// Both eyes of one frame as JPEGs.
struct PairJpeg {
  uint64_t frame_seq = 0;
  int64_t capture_stamp_ns = 0;
  EyeJpeg left;
  EyeJpeg right;
  int64_t taken_stamp_ns = 0;    ///< when the viewer took the frame (ns since epoch; 0 unknown)
  int64_t encoded_stamp_ns = 0;  ///< when both eyes were encoded (ns since epoch; 0 unknown)
  bool from_preview = false;     ///< the publisher's stereo/preview JPEGs, not encoded here
};

/// Both eyes of frame as JPEGs; error names the eye and the problem.
Result<PairJpeg> encode_pair(EyeEncoder& encoder, const stereoball_msg_StereoFrame& frame);
/// Both eyes of a stereo/preview (EyeEncoder::encode_preview); error names the eye.
Result<PairJpeg> preview_pair(EyeEncoder& encoder, const stereoball_msg_StereoPreview& preview);

/// One derived message: channel, CDR payload, stamp (ns since epoch).
struct DerivedMessage {
  foxglove::DerivedChannel channel;
  std::vector<uint8_t> cdr;
  int64_t stamp_ns = 0;
};

/// Settings of the derivation.
struct DeriverParams {
  double image_rate_hz = 10;  ///< images per second at most (0 = every frame)
  double scene_rate_hz = 15;  ///< scene updates per second at most
  EyeEncoderParams encoder;
  SceneParams scene;
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

class Deriver {
 public:
  explicit Deriver(const DeriverParams& params);
  /// Images of both eyes when the image rate allows at now_ns (monotonic ns).
  std::vector<DerivedMessage> on_frame(const stereoball_msg_StereoFrame& frame, int64_t now_ns);
  /// Images of an already encoded pair (the viewer encodes once for all its clients).
  std::vector<DerivedMessage> on_pair(const PairJpeg& pair);
  /// Annotations of both eyes.
  std::vector<DerivedMessage> on_detection(const stereoball_msg_BallDetection& m);
  /// Scene and transforms when the scene rate allows at now_ns (monotonic ns).
  std::vector<DerivedMessage> on_track(const stereoball_msg_BallTrack& m, int64_t now_ns);
  std::vector<DerivedMessage> on_truth(const stereoball_msg_GroundTruth& m, int64_t now_ns);
  void on_command(const stereoball_msg_VelocityCommand& m);
  void on_estop(const stereoball_msg_EmergencyStop& m);
  void on_health(const stereoball_msg_ComponentStatus& m);

  const Scene& scene() const { return scene_; }
  /// Frames that could not be encoded, and why the last one failed.
  uint64_t bad_frames() const { return bad_frames_; }
  const std::string& last_error() const { return last_error_; }

 private:
  std::vector<DerivedMessage> scene_messages(int64_t stamp_ns, int64_t now_ns);
  DeriverParams params_;
  EyeEncoder encoder_;
  Scene scene_;
  RateLimiter image_rate_;
  RateLimiter scene_rate_;
  uint32_t width_px_ = 640;  // of the last frame as shown, for the epipolar row's length
  double scale_ = 1.0;       // shown pixels per camera pixel of the last frame
  uint64_t bad_frames_ = 0;
  std::string last_error_;
};

}  // namespace stereoball::viewer
