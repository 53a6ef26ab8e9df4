// `stereoball calibrate live` as a process on a private DDS domain, fed real chessboard pairs
// (OpenCV's 13 stereo samples) as stereo/frame by this test acting as the cameras.

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "process.hpp"
#include "stereo/frame/frame_msg.hpp"
#include "stereo/io/calibration_file.hpp"

namespace stereoball {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

struct Pair {
  cv::Mat left, right;
};

std::vector<Pair> opencv_board_pairs() {
  std::vector<Pair> pairs;
  const std::string dir = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[16];
    std::snprintf(name, sizeof name, "%02d.jpg", i);
    Pair p{cv::imread(dir + "left" + name, cv::IMREAD_GRAYSCALE),
           cv::imread(dir + "right" + name, cv::IMREAD_GRAYSCALE)};
    if (!p.left.empty() && !p.right.empty()) pairs.push_back(p);
  }
  return pairs;
}

// Publishes stereo/frame like a 30 Hz camera pair (mono8, both eyes stamped alike).
class FakeCameras {
 public:
  FakeCameras()
      : participant_({testing::test_domain(), testing::unique_partition(), ""}),
        writer_(participant_, topics::kStereoFrame) {}

  const std::string& partition() const { return partition_; }
  bool wait_for_reader() { return writer_.wait_for_readers(1, 20'000'000'000); }

  void publish(const Pair& pair) {
    const int64_t stamp = node::now_ns();
    stereo::FrameView view;
    view.seq = seq_++;
    view.stamp_ns = stamp;
    view.encoding = "mono8";
    view.left = stereo::eye_view(pair.left, stamp);
    view.right = stereo::eye_view(pair.right, stamp);
    stereoball_msg_StereoFrame msg{};
    stereo::fill_frame_message(view, source_, msg);
    writer_.write(msg);
    std::this_thread::sleep_for(33ms);
  }

 private:
  std::string partition_ = testing::unique_partition();
  const std::string source_ = "test:opencv-samples";  // the message points at it
  dds::DomainParticipant participant_;
  dds::DataWriter<stereoball_msg_StereoFrame> writer_;
  uint64_t seq_ = 0;
};

// Whether the console lines say a held board was judged: a pose taken, or a progress line
// with the board still in both eyes for --still-s 0.3 (a pose too near one taken is not taken).
bool judged_still(const std::string& lines) {
  if (lines.find(" taken: ") != std::string::npos) return true;
  static const std::regex kStill("still L ([0-9.]+) s R ([0-9.]+) s");
  for (auto it = std::sregex_iterator(lines.begin(), lines.end(), kStill);
       it != std::sregex_iterator(); ++it) {
    if (std::min(std::stod((*it)[1]), std::stod((*it)[2])) >= 0.3) return true;
  }
  return false;
}

// Whether the console lines say no board is in view (the blank between poses was seen).
bool sees_no_board(const std::string& lines) {
  return lines.find("show the whole board") != std::string::npos;
}

// Shows pair until the tool's console lines printed from now on satisfy done, the tool exits
// or 20 s pass (then the test fails on what the tool did not take, with its output).
void show_until(FakeCameras& cameras, testing::Process& tool, const Pair& pair,
                bool (*done)(const std::string&)) {
  const std::size_t from = tool.output().size();
  const auto deadline = std::chrono::steady_clock::now() + 20s;
  while (tool.running() && std::chrono::steady_clock::now() < deadline) {
    cameras.publish(pair);
    if (done(tool.output().substr(from))) return;
  }
}

std::vector<std::string> tool_args(const std::string& partition, const std::string& out,
                                   std::vector<std::string> extra) {
  std::vector<std::string> argv{testing::bin("stereoball-calibrate-live"),
                                "--terminal",
                                "--domain",
                                std::to_string(testing::test_domain()),
                                "--partition",
                                partition,
                                "-o",
                                out};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

class CalibrateLive : public ::testing::Test {
 protected:
  void SetUp() override {
    pairs_ = opencv_board_pairs();
    if (pairs_.size() < 13) GTEST_SKIP() << "../shared/data/opencv-samples not found";
    dir_ = fs::temp_directory_path() /
           ("calibrate_live_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::vector<Pair> pairs_;
  fs::path dir_;
};

TEST_F(CalibrateLive, HeldBoardsGiveTheCalibrationTheFileToolGives) {
  // Given the tool listening and the board held still at each of the 13 sample poses
  FakeCameras cameras;
  const std::string out = (dir_ / "live.yaml").string();
  auto tool = testing::Process::start(tool_args(
      cameras.partition(), out, {"--poses", "10", "--still-s", "0.3", "--timeout-s", "200"}));
  ASSERT_TRUE(cameras.wait_for_reader()) << tool.output();
  // When each pair is held until the console has judged it (taken, or still but too near a pose
  // taken), with a blank shown between poses until the console sees no board: paced by the
  // tool's own lines, so a loaded machine takes the same poses as an idle one, only later
  const cv::Mat blank(pairs_[0].left.size(), CV_8UC1, cv::Scalar(128));
  for (const auto& pair : pairs_) {
    show_until(cameras, tool, pair, judged_still);
    show_until(cameras, tool, {blank, blank}, sees_no_board);
  }
  const auto code = tool.wait_for_exit(30s);
  // Then it takes ten poses, passes the verdict and writes a calibration whose baseline and
  // focal agree with stereoball calibrate on all 13 files
  ASSERT_TRUE(code.has_value()) << tool.output();
  EXPECT_EQ(*code, 0) << tool.output();
  EXPECT_NE(tool.output().find("pose 10 taken"), std::string::npos) << tool.output();
  EXPECT_NE(tool.output().find("verdict: PASS"), std::string::npos);
  auto live = stereo::load_calibration(out);
  ASSERT_TRUE(live) << live.error();
  const std::string files = (dir_ / "files.yaml").string();
  const std::string data = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/";
  auto [file_code, file_out] = testing::run(
      {testing::bin("stereoball-calibrate"), "--pairs", data + "stereo_calib.xml", "-o", files},
      120s);
  ASSERT_EQ(file_code, 0) << file_out;
  auto reference = stereo::load_calibration(files);
  ASSERT_TRUE(reference) << reference.error();
  EXPECT_NEAR(std::abs(live->t[0]), std::abs(reference->t[0]), 0.02 * std::abs(reference->t[0]));
  EXPECT_NEAR(live->k1(0, 0), reference->k1(0, 0), 0.02 * reference->k1(0, 0));
}

TEST_F(CalibrateLive, ABoardThatNeverStandsStillWritesNothingAndSaysWhy) {
  // Given a board that changes pose every frame
  FakeCameras cameras;
  const std::string out = (dir_ / "never.yaml").string();
  auto tool = testing::Process::start(
      tool_args(cameras.partition(), out, {"--poses", "6", "--timeout-s", "5"}));
  ASSERT_TRUE(cameras.wait_for_reader()) << tool.output();
  // When frames arrive until the tool gives up
  for (int f = 0; tool.running() && f < 400; ++f) cameras.publish(pairs_[f % pairs_.size()]);
  const auto code = tool.wait_for_exit(20s);
  // Then it exits 1, names the missing still poses and writes no file
  ASSERT_TRUE(code.has_value()) << tool.output();
  EXPECT_EQ(*code, 1) << tool.output();
  EXPECT_NE(tool.output().find("still poses taken"), std::string::npos) << tool.output();
  EXPECT_FALSE(fs::exists(out));
}

TEST_F(CalibrateLive, ABoardOfAnotherSizeIsNamedAndNothingIsWritten) {
  // Given the tool told the board has 7x5 inner corners while the cameras show 9x6
  FakeCameras cameras;
  const std::string out = (dir_ / "size.yaml").string();
  auto tool = testing::Process::start(
      tool_args(cameras.partition(), out, {"--board", "7x5", "--timeout-s", "60"}));
  ASSERT_TRUE(cameras.wait_for_reader()) << tool.output();
  // When a held board is shown until the console names the board (which takes a second of
  // frames searched, however slowly they are searched) and then the user stops the tool
  const auto deadline = std::chrono::steady_clock::now() + 50s;
  while (tool.running() && std::chrono::steady_clock::now() < deadline &&
         tool.output().find("no 7x5 board found") == std::string::npos)
    cameras.publish(pairs_[0]);
  tool.signal(SIGINT);
  const auto code = tool.wait_for_exit(20s);
  // Then the console says no 7x5 board was found and no file is written
  ASSERT_TRUE(code.has_value()) << tool.output();
  EXPECT_EQ(*code, 1);
  EXPECT_NE(tool.output().find("no 7x5 board found"), std::string::npos) << tool.output();
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace stereoball
