// sb_frame_publisher: publishes rendered stereo/frame samples (raw bgr8, or jpeg/png per eye)
// at a fixed rate with stamp_ns = publish time, for the frame transport benchmark between the
// two namespaces. Renders a few distinct frames once (simulator core) and cycles them.

#include "common/util/cli11.hpp"

#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "common/dds/writer.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/result.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "stereo/frame/frame_codec.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;

namespace {

// One eye as it goes on the wire: raw pixels or the compressed stream.
struct EncodedEye {
  std::vector<uint8_t> bytes;
  uint32_t width = 0, height = 0, step = 0;
};

// The eye as published: raw bgr8 pixels, or compressed by the publishers' shared encoder.
sb::Status encode(const cv::Mat& bgr, const std::string& encoding, int quality, EncodedEye& e) {
  e.width = static_cast<uint32_t>(bgr.cols);
  e.height = static_cast<uint32_t>(bgr.rows);
  if (encoding == "bgr8") {
    e.step = static_cast<uint32_t>(bgr.step[0]);
    e.bytes.assign(bgr.data, bgr.data + bgr.step[0] * bgr.rows);
    return {};
  }
  sb::stereo::EyeEncoder encoder({encoding, quality});
  if (auto st = encoder.encode(bgr); !st) return sb::Error{st.error()};
  e.bytes = encoder.bytes();
  return {};
}

stereoball_msg_EyeImage eye_msg(EncodedEye& e, int64_t stamp_ns) {
  stereoball_msg_EyeImage m{};
  m.capture_stamp_ns = stamp_ns;
  m.width_px = e.width;
  m.height_px = e.height;
  m.step_bytes = e.step;
  m.data._maximum = m.data._length = static_cast<uint32_t>(e.bytes.size());
  m.data._buffer = e.bytes.data();
  m.data._release = false;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{"sb_frame_publisher: publish rendered stereo frames (raw or compressed) at a rate"};
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "simulator.yaml");
  std::string encoding = "bgr8", scenario_name = "ball_rolling_away";
  int quality = 90, distinct = 10;
  double rate_hz = 30, duration_s = 10;
  app.add_option("--encoding", encoding, "bgr8, jpeg or png")
      ->check(CLI::IsMember({"bgr8", "jpeg", "png"}))
      ->capture_default_str();
  app.add_option("--quality", quality, "JPEG quality")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  app.add_option("--rate", rate_hz, "frames per second")
      ->check(CLI::Range(0.1, 1000.0))
      ->capture_default_str();
  app.add_option("--duration", duration_s, "seconds to publish")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  app.add_option("--scenario", scenario_name, "simulator scenario to render")
      ->capture_default_str();
  app.add_option("--distinct", distinct, "distinct frames rendered and cycled")
      ->check(CLI::Range(1, 300))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);

  auto params = sb::simulator::load_sim_params(common.config_path);
  if (!params) return std::fprintf(stderr, "sb_frame_publisher: %s\n", params.error().c_str()), 2;
  auto scenario = sb::simulator::load_scenario_by_name(scenario_name,
                                                       sb::node::default_config_path("scenarios"));
  if (!scenario)
    return std::fprintf(stderr, "sb_frame_publisher: %s\n", scenario.error().c_str()), 2;
  sb::simulator::Simulator sim(*params, *scenario);
  std::vector<std::pair<EncodedEye, EncodedEye>> frames;
  for (int i = 0; i < distinct; ++i) {
    const auto f = sim.step(std::nullopt, static_cast<int64_t>((0.5 + 0.2 * i) * 1e9));
    auto& [left, right] = frames.emplace_back();
    for (auto [image, eye] : {std::pair{&f.left, &left}, std::pair{&f.right, &right}}) {
      if (auto e = encode(*image, encoding, quality, *eye); !e) {
        return std::fprintf(stderr, "sb_frame_publisher: %s\n", e.error().c_str()), 1;
      }
    }
  }
  try {
    sb::node::Runner runner("frame_publisher", common);
    runner.set_heartbeat_period(0);
    sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(runner.participant(),
                                                           sb::topics::kStereoFrame);
    uint64_t seq = 0;
    const std::string source = "sb_frame_publisher";
    const int64_t start_ns = sb::node::monotonic_ns();
    runner.every(static_cast<int64_t>(1e9 / rate_hz), [&](int64_t now_ns) {
      if (sb::node::monotonic_ns() - start_ns > static_cast<int64_t>(duration_s * 1e9)) {
        runner.stop();
        return;
      }
      auto& [left, right] = frames[seq % frames.size()];
      stereoball_msg_StereoFrame m{};
      m.seq = seq++;
      m.stamp_ns = sb::node::now_ns();
      m.source = const_cast<char*>(source.c_str());
      m.encoding = const_cast<char*>(encoding.c_str());
      m.rectified = false;
      m.left = eye_msg(left, m.stamp_ns);
      m.right = eye_msg(right, m.stamp_ns);
      writer.write(m, now_ns);
    });
    std::printf("# publishing %s at %.1f Hz\n", encoding.c_str(), rate_hz);
    const int code = runner.run();
    std::printf("# sent %llu\n", static_cast<unsigned long long>(seq));
    return code;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sb_frame_publisher: %s\n", e.what());
    return 1;
  }
}
