#pragma once
// Takes stereo frames only while some client wants images: the frame reader is created when
// the first such client arrives and deleted when the last one leaves, so with no viewer
// open the camera has no extra reader to send to. Frames are taken newest-first (keep-last-1,
// loaned, never copied) only when some client would send one now (so the encoder runs at the
// rate the fastest client drains, at most max_rate_hz), JPEG-encoded once and handed to the
// server for every client.

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
  FramePump(const dds::DomainParticipant& participant, const viewer::EyeEncoderParams& encoder,
            double max_rate_hz, ViewServer& server);
  ~FramePump();
  void start();
  void stop();
  uint64_t encoded() const { return encoded_.load(); }
  uint64_t bad_frames() const { return bad_frames_.load(); }

 private:
  void run();
  const dds::DomainParticipant& participant_;
  viewer::EyeEncoder encoder_;
  double max_rate_hz_;
  ViewServer& server_;
  std::atomic<bool> stop_{false};
  std::atomic<uint64_t> encoded_{0};
  std::atomic<uint64_t> bad_frames_{0};
  std::thread thread_;
};

}  // namespace stereoball::view
