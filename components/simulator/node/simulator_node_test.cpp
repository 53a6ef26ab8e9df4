// Integration test: the real simulator process on a private domain; checks stereo/frame,
// sim/ground_truth, latched stereo/calibration and the response to cmd/velocity.

#include <gtest/gtest.h>
#include <signal.h>

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <thread>
#include <tuple>
#include <vector>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "simulator/core/rig.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "stereo/io/calibration_file.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

class SimulatorNodeTest : public ::testing::Test {
 protected:
  void start(std::vector<std::string> extra = {},
             const std::string& config = sb::testing::source_path("config/simulator.yaml")) {
    partition_ = sb::testing::unique_partition();
    std::vector<std::string> argv{sb::testing::bin("simulator"),
                                  "--config",
                                  config,
                                  "--scenario",
                                  "ball_still",
                                  "--domain",
                                  std::to_string(sb::testing::test_domain()),
                                  "--partition",
                                  partition_};
    argv.insert(argv.end(), extra.begin(), extra.end());
    node_.emplace(Process::start(argv));
    participant_.emplace(sb::dds::ParticipantOptions{sb::testing::test_domain(), partition_});
  }

  std::optional<sb::dds::Owned<stereoball_msg_StereoCalibration>> receive_calibration() {
    sb::dds::DataReader<stereoball_msg_StereoCalibration> reader(*participant_,
                                                                 sb::topics::kStereoCalibration);
    std::optional<sb::dds::Owned<stereoball_msg_StereoCalibration>> got;
    sb::testing::eventually(
        [&] {
          got = reader.take_latest();
          return got.has_value();
        },
        10s);
    return got;
  }

  std::string partition_;
  std::optional<Process> node_;
  std::optional<sb::dds::DomainParticipant> participant_;
};

TEST_F(SimulatorNodeTest, GivenLateJoiner_ThenItReceivesTheTrueCalibration) {
  // Given a running simulator that has already published frames
  start();
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(*participant_, sb::topics::kStereoFrame);
  ASSERT_TRUE(sb::testing::eventually([&] { return !frames.take().empty(); }, 10s))
      << node_->output();
  // When a calibration reader joins afterwards
  const auto calib = receive_calibration();
  // Then it receives the rig's true calibration
  ASSERT_TRUE(calib.has_value()) << node_->output();
  const sb::simulator::StereoRig rig{sb::simulator::SimParams{}};
  EXPECT_EQ((*calib)->width_px, 640u);
  EXPECT_EQ((*calib)->height_px, 480u);
  EXPECT_NEAR((*calib)->p2[3], rig.calibration().p2(0, 3), 1e-9);
  EXPECT_NEAR((*calib)->k1[0], rig.calibration().k1(0, 0), 1e-9);
  // And SIGTERM ends the node cleanly
  node_->signal(SIGTERM);
  EXPECT_EQ(node_->wait_for_exit(5s), 0) << node_->output();
}

TEST_F(SimulatorNodeTest, GivenRunning_ThenFramesAndGroundTruthArriveAtAbout30Hz) {
  // Given a running simulator
  start();
  sb::dds::DataReader<stereoball_msg_StereoFrame> frames(*participant_, sb::topics::kStereoFrame);
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth(*participant_, sb::topics::kGroundTruth);
  ASSERT_TRUE(frames.wait_for_writers(1, 10'000'000'000)) << node_->output();
  ASSERT_TRUE(truth.wait_for_writers(1, 10'000'000'000)) << node_->output();
  // When we listen for 2 s
  int frame_count = 0, truth_count = 0;
  std::optional<uint64_t> first_seq, last_seq;
  bool visible = false;
  struct Truth {
    uint64_t seq;
    int64_t stamp_ns;
    double sim_time_s;
  };
  std::vector<Truth> truths;
  const auto end = std::chrono::steady_clock::now() + 2s;
  while (std::chrono::steady_clock::now() < end) {
    for (auto& f : frames.take()) {
      ++frame_count;
      ASSERT_STREQ(f->encoding, "bgr8");
      ASSERT_EQ(f->left.width_px, 640u);
      ASSERT_EQ(f->right.height_px, 480u);
      ASSERT_EQ(f->left.data._length, 640u * 480 * 3);
      if (!first_seq) first_seq = f->seq;
      last_seq = f->seq;
    }
    for (auto& g : truth.take()) {
      ++truth_count;
      truths.push_back({g->frame_seq, g->stamp_ns, g->sim_time_s});
      visible = visible || (g->ball_present && g->ball_visible_left && g->ball_visible_right);
      EXPECT_STREQ(g->scenario, "ball_still");
    }
    std::this_thread::sleep_for(5ms);
  }
  // Then frames (keep-last-1, some may be overwritten) and ground truth flow, never faster
  // than 30 Hz, with increasing sequence numbers and the still ball visible in both eyes. How
  // many arrive depends on the machine's load (the suite runs beside compilers), so the rate is
  // checked on the stamps: exposures lie on the 30 Hz grid of simulated time (a frame whose
  // exposure passed before it could be rendered is skipped, so a step may span several grid
  // periods), and each exposure stamp advances exactly as simulated time does.
  EXPECT_GT(frame_count, 5) << node_->output();
  EXPECT_GT(truth_count, 4) << node_->output();
  EXPECT_LT(truth_count, 75);
  for (size_t i = 1; i < truths.size(); ++i) {
    ASSERT_GT(truths[i].seq, truths[i - 1].seq);
    const double dt_s = truths[i].sim_time_s - truths[i - 1].sim_time_s;
    const double periods = dt_s * 30.0;
    EXPECT_GE(periods, 1.0 - 1e-6) << "two exposures closer than 1/30 s";
    EXPECT_NEAR(periods, std::round(periods), 1e-4) << "exposure off the 30 Hz grid";
    EXPECT_NEAR(static_cast<double>(truths[i].stamp_ns - truths[i - 1].stamp_ns), dt_s * 1e9, 1e5)
        << "exposure stamps advance as simulated time";
  }
  ASSERT_TRUE(first_seq && last_seq);
  EXPECT_GT(*last_seq, *first_seq);
  EXPECT_TRUE(visible);
}

TEST_F(SimulatorNodeTest, GivenTurnLeftCommands_ThenRobotTurnsLeftAndStopsWhenTheyGoStale) {
  // Given a running simulator and a command writer
  start();
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> cmd(*participant_,
                                                          sb::topics::kVelocityCommand);
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth(*participant_, sb::topics::kGroundTruth);
  ASSERT_TRUE(cmd.wait_for_readers(1, 10'000'000'000)) << node_->output();
  auto latest = [&] {
    std::optional<sb::dds::Owned<stereoball_msg_GroundTruth>> last;
    while (auto s = truth.take_latest()) last = std::move(s);
    return last;
  };
  // When it is commanded 0.5 rad/s for 1.5 s at 20 Hz
  const auto end = std::chrono::steady_clock::now() + 1500ms;
  uint64_t seq = 0;
  while (std::chrono::steady_clock::now() < end) {
    stereoball_msg_VelocityCommand c{};
    c.seq = ++seq;
    c.stamp_ns = sb::node::now_ns();
    c.angular_radps = 0.5;
    c.source = const_cast<char*>("test");
    cmd.write(c);
    std::this_thread::sleep_for(50ms);
  }
  std::this_thread::sleep_for(100ms);
  const auto turning = latest();
  // Then it has turned left (counter-clockwise) at the commanded rate
  ASSERT_TRUE(turning.has_value()) << node_->output();
  EXPECT_NEAR((*turning)->robot_angular_radps, 0.5, 1e-6);
  EXPECT_GT((*turning)->robot_yaw_rad, 0.4);
  // And once commands stop for longer than the timeout, the base stands still
  std::this_thread::sleep_for(800ms);
  const auto stopped = latest();
  ASSERT_TRUE(stopped.has_value());
  EXPECT_EQ((*stopped)->robot_angular_radps, 0.0);
  std::this_thread::sleep_for(300ms);
  const auto later = latest();
  ASSERT_TRUE(later.has_value());
  EXPECT_EQ((*later)->robot_yaw_rad, (*stopped)->robot_yaw_rad);
}

TEST_F(SimulatorNodeTest, GivenCalibrationFile_ThenThatCalibrationIsPublished) {
  // Given a calibration file that differs from the true one (focal length off by 1%)
  const sb::simulator::StereoRig rig{sb::simulator::SimParams{}};
  sb::stereo::StereoCalibration wrong = rig.calibration();
  wrong.k1(0, 0) *= 1.01;
  const std::string path = sb::testing::temp_dir() + "/wrong.yaml";
  ASSERT_TRUE(sb::stereo::save_calibration(path, wrong).ok());
  // When the simulator is started with it
  start({"--calibration", path});
  const auto calib = receive_calibration();
  // Then the file's calibration is announced, naming the file as its source
  ASSERT_TRUE(calib.has_value()) << node_->output();
  EXPECT_NEAR((*calib)->k1[0], wrong.k1(0, 0), 1e-6);
  EXPECT_STREQ((*calib)->source, path.c_str());
}

// config/simulator.yaml with "key: value" lines replaced, written to a fresh temp file.
std::string edited_config(const std::vector<std::pair<std::string, std::string>>& edits) {
  std::ifstream in(sb::testing::source_path("config/simulator.yaml"));
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  for (const auto& [from, to] : edits) {
    const auto pos = s.find(from);
    EXPECT_NE(pos, std::string::npos) << from;
    if (pos != std::string::npos) s.replace(pos, from.size(), to);
  }
  const std::string path = sb::testing::temp_dir() + "/simulator.yaml";
  std::ofstream(path) << s;
  return path;
}

double mean_abs_diff(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat d;
  cv::absdiff(a, b, d);
  const cv::Scalar m = cv::mean(d);
  return (m[0] + m[1] + m[2]) / 3.0;
}

// Compressed frames of the node compared with the same frame rendered here by the core.
struct CompressedCheck {
  int frames = 0;
  bool contract_ok = true;           // encoding, step 0, decoded size = announced = 640x480
  double worst_own_eye_diff = 0;     // decoded eye vs its raw render, mean |diff| DN
  double best_other_eye_diff = 1e9;  // decoded left vs the raw right render (a swap shows)
  size_t max_pair_bytes = 0;
};

class SimulatorCompressedTest : public SimulatorNodeTest {
 protected:
  // Runs the node with frame_encoding `encoding` (noise off, so a frame is a pure function of
  // its simulated time) and checks `n` frames against local renders at their ground-truth time.
  CompressedCheck run(const std::string& encoding, int n) {
    const std::string config =
        edited_config({{"frame_encoding: raw", "frame_encoding: " + encoding},
                       {"noise_sigma_dn: 2.0", "noise_sigma_dn: 0.0"}});
    auto params = sb::simulator::load_sim_params(config);
    EXPECT_TRUE(params.ok()) << params.error();
    auto scenario = sb::simulator::load_scenario_by_name(
        "ball_still", sb::testing::source_path("config/scenarios"));
    EXPECT_TRUE(scenario.ok()) << scenario.error();
    CompressedCheck r;
    if (!params.ok() || !scenario.ok()) return r;
    start({}, config);
    sb::dds::DataReader<stereoball_msg_StereoFrame> frames(*participant_, sb::topics::kStereoFrame);
    sb::dds::DataReader<stereoball_msg_GroundTruth> truth(*participant_, sb::topics::kGroundTruth);
    std::map<uint64_t, double> sim_time_s;  // frame seq -> simulated time
    std::vector<sb::dds::Owned<stereoball_msg_StereoFrame>> got;
    sb::testing::eventually(
        [&] {
          for (auto& g : truth.take()) sim_time_s[g->frame_seq] = g->sim_time_s;
          for (auto& f : frames.take()) got.push_back(std::move(f));
          return static_cast<int>(got.size()) >= n;
        },
        20s);
    sb::testing::eventually(
        [&] {
          for (auto& g : truth.take()) sim_time_s[g->frame_seq] = g->sim_time_s;
          return std::all_of(got.begin(), got.end(),
                             [&](const auto& f) { return sim_time_s.count(f->seq) > 0; });
        },
        5s);
    for (const auto& f : got) {
      if (!sim_time_s.count(f->seq)) continue;
      sb::simulator::Simulator sim(*params, *scenario);
      const auto raw = sim.step(std::nullopt, std::llround(sim_time_s[f->seq] * 1e9));
      const cv::Mat left = decode(f->left), right = decode(f->right);
      r.contract_ok = r.contract_ok && encoding == f->encoding && f->left.step_bytes == 0 &&
                      f->right.step_bytes == 0 && f->left.width_px == 640 &&
                      f->left.height_px == 480 && left.size() == raw.left.size() &&
                      right.size() == raw.right.size() && left.type() == CV_8UC3;
      if (!r.contract_ok) break;
      r.worst_own_eye_diff = std::max(
          {r.worst_own_eye_diff, mean_abs_diff(left, raw.left), mean_abs_diff(right, raw.right)});
      r.best_other_eye_diff = std::min(r.best_other_eye_diff, mean_abs_diff(left, raw.right));
      r.max_pair_bytes =
          std::max<size_t>(r.max_pair_bytes, f->left.data._length + f->right.data._length);
      ++r.frames;
    }
    return r;
  }

  static cv::Mat decode(const stereoball_msg_EyeImage& eye) {
    const cv::Mat bytes(1, static_cast<int>(eye.data._length), CV_8U, eye.data._buffer);
    return cv::imdecode(bytes, cv::IMREAD_COLOR);
  }
};

TEST_F(SimulatorCompressedTest,
       GivenFrameEncodingJpeg_ThenEyesDecodeCloseToTheRawRenderAndSmaller) {
  // Given the simulator with frame_encoding jpeg (quality 90, the config's default)
  // When 10 frames arrive
  const CompressedCheck r = run("jpeg", 10);
  // Then each follows the compressed-frame contract, each eye decodes to its own raw render
  // within JPEG error, and a pair is a small fraction of the raw 2 x 640 x 480 x 3 bytes
  ASSERT_GE(r.frames, 10) << node_->output();
  EXPECT_TRUE(r.contract_ok);
  EXPECT_LT(r.worst_own_eye_diff, 2.0);
  EXPECT_GT(r.best_other_eye_diff, 3.0 * r.worst_own_eye_diff);
  const size_t raw_pair = 2u * 640 * 480 * 3;
  EXPECT_LT(r.max_pair_bytes, raw_pair / 8);
  std::printf(
      "simulator jpeg q90 (noise off): largest pair %zu bytes vs raw %zu (%.1fx), worst "
      "mean |diff| to the raw render %.2f DN\n",
      r.max_pair_bytes, raw_pair, static_cast<double>(raw_pair) / r.max_pair_bytes,
      r.worst_own_eye_diff);
}

TEST_F(SimulatorCompressedTest, GivenFrameEncodingPng_ThenEyesAreExactlyTheRawRender) {
  // Given the simulator with frame_encoding png, when 5 frames arrive
  const CompressedCheck r = run("png", 5);
  // Then they decode to exactly the raw render (lossless)
  ASSERT_GE(r.frames, 5) << node_->output();
  EXPECT_TRUE(r.contract_ok);
  EXPECT_EQ(r.worst_own_eye_diff, 0.0);
  EXPECT_LT(r.max_pair_bytes, 2u * 640 * 480 * 3);
}

TEST(SimulatorNodeCli, GivenBadFrameEncodingOrQuality_ThenOneLineNamingFileAndKey) {
  const std::string bin = sb::testing::bin("simulator");
  for (const auto& [from, to, key] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {"frame_encoding: raw", "frame_encoding: gif", "frame_encoding"},
           {"jpeg_quality: 90", "jpeg_quality: 0", "jpeg_quality"},
           {"max_linear_brake_mps2: 4.0", "max_linear_brake_mps2: -1",
            "robot.max_linear_brake_mps2"}}) {
    const std::string config = edited_config({{from, to}});
    const auto [code, out] = sb::testing::run({bin, "--config", config}, 10s);
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find(config), std::string::npos) << out;
    EXPECT_NE(out.find(key), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  }
  // And out-of-range override flags are refused, naming the flag
  for (const auto& [flag, bad] : std::vector<std::pair<std::string, std::string>>{
           {"--jpeg-quality", "0"}, {"--jpeg-chroma", "411"}}) {
    const auto [code, out] = sb::testing::run(
        {bin, "--config", sb::testing::source_path("config/simulator.yaml"), flag, bad}, 10s);
    EXPECT_NE(code, 0) << out;
    EXPECT_NE(out.find(flag), std::string::npos) << out;
  }
}

TEST(SimulatorNodeCli, GivenBadInputs_ThenOneClearLineAndNonZeroExit) {
  const std::string bin = sb::testing::bin("simulator");
  const std::string config = sb::testing::source_path("config/simulator.yaml");
  // Unknown scenario
  auto [code, out] = sb::testing::run({bin, "--config", config, "--scenario", "nope"}, 10s);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("scenario 'nope'"), std::string::npos) << out;
  // Missing config file
  std::tie(code, out) = sb::testing::run({bin, "--config", "/nonexistent/sim.yaml"}, 10s);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("/nonexistent/sim.yaml"), std::string::npos) << out;
  // Calibration of another image size
  sb::simulator::SimParams small;
  small.width_px = 352;
  small.height_px = 288;
  const std::string path = sb::testing::temp_dir() + "/small.yaml";
  ASSERT_TRUE(
      sb::stereo::save_calibration(path, sb::simulator::StereoRig(small).calibration()).ok());
  std::tie(code, out) = sb::testing::run({bin, "--config", config, "--calibration", path}, 10s);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("does not match"), std::string::npos) << out;
}

}  // namespace
