#pragma once
// stereo/preview beside a frame publisher (camera_server, simulator), like image_transport's
// compressed stream: a preview is made only while some reader of stereo/preview is matched, so
// with no viewer open the robot pays one matched-reader check per frame and nothing else. It
// is made off the capture path: offer() is called after the frame itself was published and
// only copies the eyes into a one-slot mailbox (the newest frame wins); a worker thread at low
// priority (normal policy, nice 10) encodes (preview_encoder.hpp) and publishes.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/writer.hpp"
#include "stereo/frame/frame_codec.hpp"
#include "stereo/frame/frame_view.hpp"
#include "stereoball.h"

namespace stereoball::stereo {

class PreviewPublisher {
 public:
  /// params must be valid with preview_max_width_px > 0; source is the frames' source text.
  PreviewPublisher(const dds::DomainParticipant& participant, const FrameCodecParams& params,
                   std::string source);
  ~PreviewPublisher();
  PreviewPublisher(const PreviewPublisher&) = delete;
  PreviewPublisher& operator=(const PreviewPublisher&) = delete;

  /// The frame just published (raw: bgr8, mono8 or yuyv). With no preview reader matched,
  /// returns at once; otherwise copies the eyes for the worker, replacing a frame it has not
  /// started on yet.
  void offer(const FrameView& view);

  uint64_t published() const { return published_.load(); }
  /// Readers of stereo/preview matched now.
  uint32_t matched_readers() const { return writer_.matched_readers(); }
  /// Encode time of the last preview (both eyes), microseconds.
  uint64_t encode_us() const { return encode_us_.load(); }
  /// The newest encoding error not yet collected (the node reports it as health error).
  std::optional<std::string> take_error();

 private:
  struct Slot {
    FrameView view;  // points into left/right
    std::vector<uint8_t> left, right;
  };
  void run(FrameCodecParams params);

  std::string source_;
  dds::DataWriter<stereoball_msg_StereoPreview> writer_;
  std::mutex mutex_;
  std::condition_variable wake_;
  Slot pending_;  // guarded by mutex_
  bool has_pending_ = false;
  bool stop_ = false;
  std::optional<std::string> error_;
  std::atomic<uint64_t> published_{0};
  std::atomic<uint64_t> encode_us_{0};
  std::thread worker_;
};

}  // namespace stereoball::stereo
