#pragma once
// Takes stereo pairs only while some client wants images: the readers are created when the
// first such client arrives and deleted when the last one leaves, so with no viewer open the
// robot has no extra reader to send to (and makes no preview). A publisher's stereo/preview
// (JPEG eyes made on the robot only while read, stereo/frame/preview_publisher.hpp) is
// preferred: it is forwarded without decoding or encoding here and the raw frames are not
// sent to this process at all. When no publisher offers a preview (JPEG cameras, other
// publishers, preview_max_width_px 0) the pump reads stereo/frame instead. Pairs are taken
// newest-first (keep-last-1, loaned, never copied) only when some client would send one now
// (so the encoder runs at the rate the fastest client drains, at most max_rate_hz), made into
// JPEGs once and handed to the server for every client.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "common/dds/participant.hpp"
#include "view_server.hpp"
#include "viewer/bridge/eye_encoder.hpp"

namespace stereoball::view {

class FramePump {
 public:
  /// use_preview false: always stereo/frame (the preview is neither read nor asked for).
  FramePump(const dds::DomainParticipant& participant, const viewer::EyeEncoderParams& encoder,
            double max_rate_hz, bool use_preview, ViewServer& server);
  ~FramePump();
  void start();
  void stop();
  uint64_t bad_frames() const { return bad_frames_.load(); }

 private:
  void run();
  const dds::DomainParticipant& participant_;
  viewer::EyeEncoder encoder_;
  double max_rate_hz_;
  bool use_preview_;
  ViewServer& server_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> bad_frames_{0};
  std::thread thread_;
};

}  // namespace stereoball::view
