#include "stereo/frame/preview_publisher.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

#include "stereo/frame/frame_msg.hpp"
#include "stereo/frame/preview_encoder.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::stereo {
namespace {

void copy_eye(const EyeView& from, std::vector<uint8_t>& bytes, EyeView& to) {
  bytes.resize(from.bytes);  // same size frame after frame: no allocation after the first
  if (from.bytes > 0) std::memcpy(bytes.data(), from.data, from.bytes);
  to = from;
  to.data = bytes.data();
}

int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// The preview is for people: it must never delay the robot's own work. A publisher started
// with a real-time policy (chrt) would hand it to this thread, so it goes back to the normal
// policy, at nice 10 (a tenth of a nice-0 thread's share when both want the CPU: enough for
// ~4 % of a core of encoding on a loaded host). Only lowering, which needs no privilege;
// failing that it keeps what it has.
void yield_to_the_robot() {
  sched_param normal{};
  normal.sched_priority = 0;
  pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), 10);
}

}  // namespace

PreviewPublisher::PreviewPublisher(const dds::DomainParticipant& participant,
                                   const FrameCodecParams& params, std::string source)
    : source_(std::move(source)), writer_(participant, topics::kStereoPreview) {
  worker_ = std::thread([this, params] { run(params); });
}

PreviewPublisher::~PreviewPublisher() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  worker_.join();
}

void PreviewPublisher::offer(const FrameView& view) {
  // The only cost while nobody watches: one look at the matched-reader count.
  if (writer_.matched_readers() == 0) return;
  {
    std::lock_guard lock(mutex_);
    pending_.view = view;
    copy_eye(view.left, pending_.left, pending_.view.left);
    copy_eye(view.right, pending_.right, pending_.view.right);
    has_pending_ = true;
  }
  wake_.notify_one();
}

std::optional<std::string> PreviewPublisher::take_error() {
  std::lock_guard lock(mutex_);
  return std::exchange(error_, std::nullopt);
}

void PreviewPublisher::run(FrameCodecParams params) {
  pthread_setname_np(pthread_self(), "preview");  // its CPU shows per thread
  yield_to_the_robot();
  PreviewEncoder encoder(params);
  Slot working;
  while (true) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || has_pending_; });
      if (stop_) return;
      // Swapping moves the buffers with the view that points into them.
      std::swap(working, pending_);
      has_pending_ = false;
    }
    const int64_t start_us = steady_us();
    auto preview = encoder.step(working.view);
    if (!preview) {
      std::lock_guard lock(mutex_);
      error_ = preview.error();
      continue;
    }
    stereoball_msg_StereoPreview msg{};
    msg.seq = preview->view.seq;
    msg.stamp_ns = preview->view.stamp_ns;
    msg.source = const_cast<char*>(source_.c_str());
    msg.source_width_px = preview->source_width_px;
    msg.source_height_px = preview->source_height_px;
    fill_eye_message(preview->view.left, msg.left);
    fill_eye_message(preview->view.right, msg.right);
    try {
      writer_.write(msg, msg.stamp_ns);
    } catch (const std::exception& e) {
      std::lock_guard lock(mutex_);
      error_ = std::string("stereo/preview: ") + e.what();
      continue;
    }
    encode_us_ = static_cast<uint64_t>(steady_us() - start_us);
    ++published_;
  }
}

}  // namespace stereoball::stereo
