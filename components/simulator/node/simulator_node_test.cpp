// Integration test: the real simulator process on a private domain; checks stereo/frame,
// sim/ground_truth, latched stereo/calibration and the response to cmd/velocity.

#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <optional>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "simulator/core/rig.hpp"
#include "stereo/io/calibration_file.hpp"

namespace sb = stereoball;
using namespace std::chrono_literals;
using sb::testing::Process;

namespace {

class SimulatorNodeTest : public ::testing::Test {
 protected:
  void start(std::vector<std::string> extra = {}) {
    partition_ = sb::testing::unique_partition();
    std::vector<std::string> argv{sb::testing::bin("simulator"),
                                  "--config",
                                  sb::testing::source_path("config/simulator.yaml"),
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
      visible = visible || (g->ball_present && g->ball_visible_left && g->ball_visible_right);
      EXPECT_STREQ(g->scenario, "ball_still");
    }
    std::this_thread::sleep_for(5ms);
  }
  // Then frames (keep-last-1, some may be overwritten) and ground truth flow at about 30 Hz,
  // with increasing sequence numbers and the still ball visible in both eyes
  EXPECT_GT(frame_count, 20) << node_->output();
  EXPECT_GT(truth_count, 40) << node_->output();
  EXPECT_LT(truth_count, 75);
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
  ASSERT_FALSE(sb::stereo::save_calibration(path, wrong).has_value());
  // When the simulator is started with it
  start({"--calibration", path});
  const auto calib = receive_calibration();
  // Then the file's calibration is announced, naming the file as its source
  ASSERT_TRUE(calib.has_value()) << node_->output();
  EXPECT_NEAR((*calib)->k1[0], wrong.k1(0, 0), 1e-6);
  EXPECT_STREQ((*calib)->source, path.c_str());
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
  ASSERT_FALSE(sb::stereo::save_calibration(path, sb::simulator::StereoRig(small).calibration())
                   .has_value());
  std::tie(code, out) = sb::testing::run({bin, "--config", config, "--calibration", path}, 10s);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("does not match"), std::string::npos) << out;
}

}  // namespace
