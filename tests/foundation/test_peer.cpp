// sb_test_peer: a minimal node built exactly like the real ones (Runner, params file,
// topic table), used by the foundation tests.
//   echo TOPIC            take every sample of TOPIC (typed) and write it again (typed)
//                         into partition "<partition>.echo"
//   publish-frames N      publish N 640x480 stereo frames, seq 0..N-1, as fast as possible
// Params (--config): peer.label (string), peer.delay_ms (int 0..1000, delay before echoing).

#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "common/params/params_file.hpp"
#include "common/util/log.hpp"
#include "samples.hpp"

namespace sb = stereoball;

namespace {

struct PeerParams {
  std::string label = "peer";
  int delay_ms = 0;
};

sb::Result<PeerParams> load_params(const std::string& path) {
  auto file = sb::params::ParamsFile::load(path);
  if (!file) return sb::Error{file.error()};
  PeerParams p;
  file->read("peer.label", p.label);
  file->read("peer.delay_ms", p.delay_ms, 0, 1000);
  if (auto st = file->finish(); !st) return sb::Error{st.error()};
  return p;
}

template <typename T>
struct Echo {
  Echo(sb::node::Runner& runner, sb::dds::DomainParticipant& out_participant,
       const sb::topics::Topic<T>& topic, int delay_ms)
      : reader(runner.participant(), topic), writer(out_participant, topic) {
    runner.on_data(reader.handle(), [this, &runner, delay_ms] {
      for (auto& sample : reader.take()) {
        if (delay_ms) std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
        // An echo: authenticated samples go back with their tag, exactly as they came.
        if constexpr (sb::dds::Authenticated<T>) {
          writer.forward(*sample);
        } else {
          writer.write(*sample);
        }
        runner.health().count(std::string(this->reader.spec().name));
      }
    });
  }
  sb::dds::DataReader<T> reader;
  sb::dds::DataWriter<T> writer;
};

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{"sb_test_peer: test node"};
  app.require_subcommand(1);
  app.fallthrough();
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common,
                             std::string(SB_SOURCE_DIR) + "/tests/foundation/test_peer.yaml");
  std::string topic_name;
  auto* echo = app.add_subcommand("echo", "echo a topic into <partition>.echo");
  echo->add_option("topic", topic_name)->required();
  int frames = 0;
  auto* publish = app.add_subcommand("publish-frames", "publish N stereo frames");
  publish->add_option("count", frames)->required();
  CLI11_PARSE(app, argc, argv);

  auto params = load_params(common.config_path);
  if (!params) {
    std::fprintf(stderr, "sb_test_peer: %s\n", params.error().c_str());
    return 2;
  }
  try {
    sb::node::Runner runner("sb_test_peer", common);
    if (publish->parsed()) {
      sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(runner.participant(),
                                                             sb::topics::kStereoFrame);
      writer.wait_for_readers(1, 5'000'000'000);
      for (int i = 0; i < frames; ++i) {
        sb::testing::SampleStorage storage;
        stereoball_msg_StereoFrame frame{};
        sb::testing::fill(frame, storage, static_cast<uint32_t>(i));
        frame.seq = static_cast<uint64_t>(i);
        writer.write(frame);
        // Paced so loopback delivers every frame; the test checks what the reader keeps.
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      std::printf("published %d frames\n", frames);
      std::fflush(stdout);
      return runner.run();
    }
    sb::dds::DomainParticipant out({common.domain_id, common.partition + ".echo"});
    std::vector<std::shared_ptr<void>> echoes;
    sb::topics::for_each([&](const auto& topic) {
      using T = typename std::decay_t<decltype(topic)>::Type;
      if (topic.spec.name == topic_name) {
        echoes.push_back(std::make_shared<Echo<T>>(runner, out, topic, params->delay_ms));
      }
    });
    if (echoes.empty()) {
      std::fprintf(stderr, "sb_test_peer: unknown topic '%s'\n", topic_name.c_str());
      return 2;
    }
    sb::log::info("echoing ", topic_name, " as ", params->label);
    return runner.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sb_test_peer: %s\n", e.what());
    return 1;
  }
}
