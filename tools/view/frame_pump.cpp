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

// How long a new stereo/preview reader waits for a publisher before the raw frames are read:
// endpoint discovery between participants that already know each other takes milliseconds
// on one host; a viewer of a publisher without previews shows its first image this much
// later, and a preview found later still takes over.
constexpr int64_t kPreviewDiscoveryNs = 1'000'000'000;

// A reader with its waitset, alive only while images are wanted.
template <typename T>
struct Subscription {
  Subscription(const dds::DomainParticipant& p, const topics::Topic<T>& topic)
      : reader(p, topic), condition(reader.handle()), waitset(p) {
    waitset.attach(condition.handle(), 1);
  }
  dds::DataReader<T> reader;
  dds::ReadCondition condition;
  dds::WaitSet waitset;
};

// The newest sample of sub (waiting at most 100 ms for one) made into a pair by make; nothing
// when none came or the rate limit refuses it now.
template <typename T, typename Make>
std::optional<Result<viewer::PairJpeg>> next_pair(Subscription<T>& sub,
                                                  viewer::RateLimiter& limiter, Make make,
                                                  uint64_t& seq) {
  sub.waitset.wait(100'000'000);
  auto loaned = sub.reader.take_loaned();
  const auto newest = loaned.latest_valid();
  if (!newest || !limiter.admit(node::monotonic_ns())) return std::nullopt;
  seq = loaned[*newest].seq;
  return make(loaned[*newest]);
}

}  // namespace

FramePump::FramePump(const dds::DomainParticipant& participant,
                     const viewer::EyeEncoderParams& encoder, double max_rate_hz, bool use_preview,
                     ViewServer& server)
    : participant_(participant),
      encoder_(encoder),
      max_rate_hz_(max_rate_hz),
      use_preview_(use_preview),
      server_(server) {}

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
  std::unique_ptr<Subscription<stereoball_msg_StereoPreview>> previews;
  std::unique_ptr<Subscription<stereoball_msg_StereoFrame>> frames;
  int64_t previews_since_ns = 0;
  viewer::RateLimiter limiter(max_rate_hz_);
  log::Throttle throttle(5'000'000'000);
  while (!stop_) {
    if (!server_.images_wanted()) {
      previews.reset();
      frames.reset();
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      continue;
    }
    try {
      const int64_t now = node::monotonic_ns();
      if (use_preview_ && !previews) {
        previews = std::make_unique<Subscription<stereoball_msg_StereoPreview>>(
            participant_, topics::kStereoPreview);
        previews_since_ns = now;
      }
      // A preview offered: the raw frames are not read (nor sent here). None offered after the
      // discovery time: the raw frames are, until a preview publisher appears.
      const bool preview = previews && previews->reader.matched_writers() > 0;
      if (preview) {
        frames.reset();
      } else if (!frames && (!previews || now - previews_since_ns > kPreviewDiscoveryNs)) {
        frames = std::make_unique<Subscription<stereoball_msg_StereoFrame>>(participant_,
                                                                            topics::kStereoFrame);
      }
      if (!preview && !frames) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        continue;
      }
      // Skip frames rather than queue them: a frame is taken (and deserialised and encoded)
      // only when some client would send it now; meanwhile keep-last-1 holds just the newest.
      if (!server_.wait_until_ready_for_image(100'000'000)) continue;
      // Over the rate limit, wait rather than take a frame and drop it (keep-last-1 holds the
      // newest meanwhile).
      if (const int64_t wait = limiter.wait_ns(node::monotonic_ns()); wait > 0) {
        std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
        continue;
      }
      int64_t taken_ns = 0;
      uint64_t seq = 0;
      auto pair = preview ? next_pair(
                                *previews, limiter,
                                [&](const stereoball_msg_StereoPreview& p) {
                                  taken_ns = node::now_ns();
                                  return viewer::preview_pair(encoder_, p);
                                },
                                seq)
                          : next_pair(
                                *frames, limiter,
                                [&](const stereoball_msg_StereoFrame& f) {
                                  taken_ns = node::now_ns();
                                  return viewer::encode_pair(encoder_, f);
                                },
                                seq);
      if (!pair) continue;
      if (!*pair) {
        ++bad_frames_;
        if (throttle.allow(node::monotonic_ns()))
          log::warn(preview ? "preview " : "frame ", seq, " not shown: ", pair->error());
        continue;
      }
      (*pair)->taken_stamp_ns = taken_ns;
      (*pair)->encoded_stamp_ns = node::now_ns();
      server_.publish_pair(std::make_shared<const viewer::PairJpeg>(std::move(**pair)));
    } catch (const std::exception& e) {
      log::error("frame reader: ", e.what());
      previews.reset();
      frames.reset();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  }
}

}  // namespace stereoball::view
