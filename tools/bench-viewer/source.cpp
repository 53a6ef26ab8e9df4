#include "source.hpp"

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <regex>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::bench {
namespace {

class Demo : public Source {
 public:
  Demo(int domain, const std::string& scenario, const std::string& work_dir)
      : scenario_(scenario),
        child_({sibling_program("stereoball-demo"), "--scenario", scenario, "--duration", "3600",
                "--domain", std::to_string(domain), "--out", work_dir + "/demo"},
               work_dir + "/demo.log") {}
  Child& child() { return child_; }
  std::string partition() const override { return "demo." + std::to_string(child_.pid()) + ".*"; }
  std::vector<pid_t> robot_processes() const override { return children_of(child_.pid()); }
  std::string describe() const override { return "stereoball demo, scenario " + scenario_; }

 private:
  std::string scenario_;
  Child child_;
};

class Synthetic : public Source {
 public:
  Synthetic(int domain, int width, int height, double rate_hz, bool jpeg)
      : partition_("bench.viewer." + std::to_string(getpid())),
        describe_("synthetic " + std::to_string(width) + "x" + std::to_string(height) +
                  (jpeg ? " jpeg" : " bgr8") + " stereo pair published by the benchmark"),
        jpeg_(jpeg) {
    thread_ = std::thread([=, this] { publish(domain, width, height, rate_hz); });
  }
  ~Synthetic() override {
    stop_ = true;
    thread_.join();
  }
  std::string partition() const override { return partition_; }
  std::vector<pid_t> robot_processes() const override { return {}; }
  std::string describe() const override { return describe_; }

 private:
  void publish(int domain, int width, int height, double rate_hz);
  std::string partition_, describe_;
  bool jpeg_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

void Synthetic::publish(int domain, int width, int height, double rate_hz) {
  dds::DomainParticipant p({domain, partition_});
  dds::DataWriter<stereoball_msg_StereoFrame> frames(p, topics::kStereoFrame);
  dds::DataWriter<stereoball_msg_BallDetection> detections(p, topics::kBallDetection);
  dds::DataWriter<stereoball_msg_BallTrack> tracks(p, topics::kBallTrack);
  dds::DataWriter<stereoball_msg_GroundTruth> truth(p, topics::kGroundTruth);
  // A texture wider than the image, shifted a little every frame: JPEG sizes are those of a
  // moving, busy scene (harder to compress than the simulator's), at one copy per frame.
  const int margin = 256;
  const int wide = width + margin;
  std::vector<uint8_t> texture(static_cast<size_t>(wide) * height * 3);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < wide; ++x) {
      uint8_t* px = &texture[(static_cast<size_t>(y) * wide + x) * 3];
      const double v = std::sin(x * 0.05) * std::cos(y * 0.07);
      px[0] = static_cast<uint8_t>(128 + 100 * v);
      px[1] = static_cast<uint8_t>((x ^ y) & 0xff);
      px[2] = static_cast<uint8_t>(128 - 100 * v);
    }
  std::vector<uint8_t> image(static_cast<size_t>(width) * height * 3);
  auto shifted = [&](uint64_t seq) {
    const size_t shift = (seq * 3) % margin;
    for (int y = 0; y < height; ++y)
      std::memcpy(&image[static_cast<size_t>(y) * width * 3],
                  &texture[(static_cast<size_t>(y) * wide + shift) * 3],
                  static_cast<size_t>(width) * 3);
  };
  // JPEG cameras: a cycle of frames compressed beforehand (q80, as camera_server's default),
  // so the benchmark's own encoding costs nothing while it runs.
  std::vector<std::vector<uint8_t>> jpegs;
  for (uint64_t seq = 0; jpeg_ && seq < 32; ++seq) {
    shifted(seq);
    jpegs.emplace_back();
    cv::imencode(".jpg", cv::Mat(height, width, CV_8UC3, image.data()), jpegs.back(),
                 {cv::IMWRITE_JPEG_QUALITY, 80});
  }
  char source[] = "bench", reason[] = "bench", scenario[] = "bench";
  char bgr8[] = "bgr8", jpeg_encoding[] = "jpeg";
  const auto period = std::chrono::nanoseconds(static_cast<int64_t>(1e9 / rate_hz));
  auto next = std::chrono::steady_clock::now();
  for (uint64_t seq = 0; !stop_; ++seq) {
    if (!jpeg_) shifted(seq);
    auto& bytes = jpeg_ ? jpegs[seq % jpegs.size()] : image;
    stereoball_msg_StereoFrame f{};
    f.seq = seq;
    f.stamp_ns = node::now_ns();
    f.source = source;
    f.encoding = jpeg_ ? jpeg_encoding : bgr8;
    for (auto* eye : {&f.left, &f.right}) {
      eye->capture_stamp_ns = f.stamp_ns;
      eye->width_px = static_cast<uint32_t>(width);
      eye->height_px = static_cast<uint32_t>(height);
      eye->step_bytes = jpeg_ ? 0 : static_cast<uint32_t>(width * 3);
      eye->data._buffer = bytes.data();
      eye->data._length = static_cast<uint32_t>(bytes.size());
    }
    frames.write(f);
    stereoball_msg_BallDetection d{};
    d.frame_seq = seq;
    d.capture_stamp_ns = f.stamp_ns;
    d.reason = reason;
    d.left = {320, 240, 20, 0.9f};
    detections.write(d);
    stereoball_msg_BallTrack t{};
    t.frame_seq = seq;
    t.capture_stamp_ns = f.stamp_ns;
    t.reason = reason;
    tracks.write(t);
    stereoball_msg_GroundTruth g{};
    g.frame_seq = seq;
    g.stamp_ns = f.stamp_ns;
    g.scenario = scenario;
    truth.write(g);
    next += period;
    std::this_thread::sleep_until(next);
  }
}

}  // namespace

std::unique_ptr<Source> start_demo(int domain, const std::string& scenario,
                                   const std::string& work_dir, std::string& error) {
  auto demo = std::make_unique<Demo>(domain, scenario, work_dir);
  // The demo prints its progress line once its nodes run and frames flow.
  if (!demo->child().wait_for_log(std::regex(R"(t=\s*[0-9.]+ s\s+[0-9.]+ fps)"), 120)) {
    error = "the demo did not start (see " + work_dir + "/demo.log)";
    return nullptr;
  }
  return demo;
}

std::unique_ptr<Source> start_synthetic(int domain, int width, int height, double rate_hz,
                                        bool jpeg) {
  return std::make_unique<Synthetic>(domain, width, height, rate_hz, jpeg);
}

FrameRate::FrameRate(int domain, const std::string& partition) {
  thread_ = std::thread([this, domain, partition] {
    dds::DomainParticipant p({domain, partition});
    dds::DataReader<stereoball_msg_GroundTruth> truth(p, topics::kGroundTruth);
    while (!stop_) {
      for (auto& s : truth.take(64)) {
        std::lock_guard lock(mutex_);
        count_.sample(s->frame_seq, node::monotonic_ns());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
}

FrameRate::~FrameRate() {
  stop_ = true;
  thread_.join();
}

void FrameRate::restart() {
  std::lock_guard lock(mutex_);
  count_.restart();
}

double FrameRate::rate_hz() const {
  std::lock_guard lock(mutex_);
  return count_.rate_hz();
}

}  // namespace stereoball::bench
