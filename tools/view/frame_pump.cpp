#include "frame_pump.hpp"

#include <pthread.h>

#include <chrono>
#include <memory>

#include "common/dds/reader.hpp"
#include "common/dds/waitset.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/log.hpp"
#include "stereoball/topics.hpp"
#include "viewer/bridge/derived_channels.hpp"
#include "viewer/core/flow.hpp"

namespace stereoball::view {
namespace {

// A frame reader with its waitset, alive only while images are wanted.
struct Subscription {
  explicit Subscription(const dds::DomainParticipant& p)
      : reader(p, topics::kStereoFrame), condition(reader.handle()), waitset(p) {
    waitset.attach(condition.handle(), 1);
  }
  dds::DataReader<stereoball_msg_StereoFrame> reader;
  dds::ReadCondition condition;
  dds::WaitSet waitset;
};

}  // namespace

FramePump::FramePump(const dds::DomainParticipant& participant,
                     const viewer::EyeEncoderParams& encoder, double max_rate_hz,
                     ViewServer& server)
    : participant_(participant), encoder_(encoder), max_rate_hz_(max_rate_hz), server_(server) {}

FramePump::~FramePump() {
  stop();
}

void FramePump::start() {
  thread_ = std::thread([this] { run(); });
}

void FramePump::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void FramePump::run() {
  pthread_setname_np(pthread_self(), "view-frames");  // per-thread CPU in the benchmark
  std::unique_ptr<Subscription> sub;
  viewer::RateLimiter limiter(max_rate_hz_);
  log::Throttle throttle(5'000'000'000);
  while (!stop_) {
    if (!server_.images_wanted()) {
      sub.reset();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      continue;
    }
    try {
      if (!sub) sub = std::make_unique<Subscription>(participant_);
      // Skip frames rather than queue them: a frame is taken (and deserialised and encoded)
      // only when some client would send it now; meanwhile keep-last-1 holds just the newest.
      if (!server_.wait_until_ready_for_image(100'000'000)) continue;
      // Over the rate limit, wait rather than take a frame and drop it (keep-last-1 holds the
      // newest meanwhile).
      if (const int64_t wait = limiter.wait_ns(node::monotonic_ns()); wait > 0) {
        std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
        continue;
      }
      sub->waitset.wait(100'000'000);
      auto loaned = sub->reader.take_loaned();
      const auto newest = loaned.latest_valid();
      if (!newest || !limiter.admit(node::monotonic_ns())) continue;
      const int64_t taken_ns = node::now_ns();
      auto pair = viewer::encode_pair(encoder_, loaned[*newest]);
      if (!pair) {
        ++bad_frames_;
        if (throttle.allow(node::monotonic_ns()))
          log::warn("frame ", loaned[*newest].seq, " not shown: ", pair.error());
        continue;
      }
      pair->taken_stamp_ns = taken_ns;
      pair->encoded_stamp_ns = node::now_ns();
      ++encoded_;
      server_.publish_pair(std::make_shared<const viewer::PairJpeg>(std::move(*pair)));
    } catch (const std::exception& e) {
      log::error("frame reader: ", e.what());
      sub.reset();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
}

}  // namespace stereoball::view
