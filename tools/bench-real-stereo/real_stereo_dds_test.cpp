// The bench's runners on three real pairs of the shared set with a hand-made truth in which one
// pair's ball is deliberately placed elsewhere: every pair gets exactly one detection and the
// displaced pair is not scored correct.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "process.hpp"
#include "real_stereo_report.hpp"
#include "real_stereo_run.hpp"
#include "real_stereo_set.hpp"

namespace fs = std::filesystem;
namespace rs = stereoball::real_stereo;

namespace {

const std::string kShared = std::string(SB_SHARED_DATA_DIR) + "/real-stereo-basketball";

// Pairs 2, 4 and 9 as in ball_truth.csv, pair 4's left ball moved 400 px to the left.
const char* kTruth =
    "pair,left,right,rect_left_cx,rect_left_cy,rect_right_cx,rect_right_cy,rect_left_r,"
    "rect_right_r,dy_mean,Z_m,flag\n"
    "2,left_02.jpg,right_02.jpg,1222.5,541.5,1137.5,541.0,71.0,71.0,0.5,1.62,\n"
    "4,left_04.jpg,right_04.jpg,1118.5,589.0,1435.5,590.5,70.0,69.0,-1.5,1.66,moved_on_purpose\n"
    "9,left_09.jpg,right_09.jpg,1312.5,1203.0,1174.5,1201.0,110.0,110.0,2.0,1.0,\n";

// A set folder of links to three shared pairs, the hand-made truth and the rig's calibration.
std::string make_set() {
  const std::string dir = stereoball::testing::temp_dir() + "/set";
  fs::create_directories(dir + "/left");
  fs::create_directories(dir + "/right");
  fs::create_directories(dir + "/calibration");
  for (const char* n : {"02", "04", "09"}) {
    for (const std::string eye : {"left", "right"}) {
      const std::string name = eye + "_" + n + ".jpg";
      fs::create_symlink(kShared + "/" + eye + "/" + name, dir + "/" + eye + "/" + name);
    }
  }
  fs::create_symlink(kShared + "/calibration/rig_2304x1296.yaml",
                     dir + "/calibration/rig_2304x1296.yaml");
  std::ofstream(dir + "/ball_truth.csv") << kTruth;
  return dir;
}

rs::DetectorConfig config(bool raise_limit) {
  rs::DetectorOverrides o;
  o.ball_diameter_m = 0.24;
  o.no_floor_check = true;
  if (raise_limit) o.image_limit = cv::Size(2304, 1296);
  auto c =
      rs::compose_detector_config(std::string(SB_SOURCE_DIR) + "/config/ball_detector.yaml", o);
  EXPECT_TRUE(c.ok()) << c.error();
  return *c;
}

}  // namespace

TEST(RealStereoDds,
     GivenThreeRealPairsWhenPlayedOverDdsThenEachGetsOneDetectionAndTheMovedTruthIsNotCorrect) {
  if (!fs::exists(kShared + "/ball_truth.csv"))
    GTEST_SKIP() << "shared data absent: " << kShared << " (../shared/data of the project)";
  // Given the three pairs, the detector raised to their size, a private domain
  auto set = rs::open_set(make_set());
  ASSERT_TRUE(set.ok()) << set.error();
  rs::RunOptions options;
  options.bin_dir = SB_BIN_DIR;
  options.domain = stereoball::testing::test_domain();
  options.partition = stereoball::testing::unique_partition();
  options.rate_hz = 1.0;
  options.warmup_s = 8.0;  // the first frames of a calibration take seconds on a busy machine
  // When the DDS runner plays them through camera_server and ball_detector
  const rs::RunResult run = rs::run_dds(*set, config(true), options);
  // Then it ran without errors and every pair got its detection
  for (const auto& e : run.errors) ADD_FAILURE() << "run error: " << e;
  ASSERT_EQ(run.pairs.size(), 3u);
  const auto scores = rs::score_run(*set, run);
  EXPECT_EQ(scores.size(), 3u);
  for (const auto& p : run.pairs) EXPECT_TRUE(p.detection.has_value());
  // And the pair whose truth was moved is wrong or missed, never correct
  for (const auto& s : scores) {
    if (s.truth.pair == "4") {
      EXPECT_NE(s.verdict, rs::Verdict::kCorrect) << s.why;
    }
    EXPECT_NE(s.verdict, rs::Verdict::kExcluded);
  }
  const auto summary = rs::summarize(scores);
  EXPECT_EQ(summary.overall.total(), 3);
  EXPECT_EQ(summary.timed_frames, 3u);
}

TEST(RealStereoInProcess, GivenTheShippedImageLimitWhenRunThenTheRefusalIsARunErrorNotAMiss) {
  if (!fs::exists(kShared + "/ball_truth.csv"))
    GTEST_SKIP() << "shared data absent: " << kShared << " (../shared/data of the project)";
  // Given the shipped 1920x1080 image limit and 2304x1296 pairs
  auto set = rs::open_set(make_set());
  ASSERT_TRUE(set.ok()) << set.error();
  // When run in-process
  const rs::RunResult run = rs::run_in_process(*set, config(false), {});
  // Then nothing is scored and the error says how to raise the limit
  ASSERT_FALSE(run.errors.empty());
  EXPECT_NE(run.errors.front().find("--image-limit"), std::string::npos) << run.errors.front();
  EXPECT_TRUE(rs::score_run(*set, run).empty());
}

TEST(RealStereoSet, GivenATruthRowNamingAMissingImageWhenOpenedThenTheErrorNamesFileAndLine) {
  if (!fs::exists(kShared + "/ball_truth.csv"))
    GTEST_SKIP() << "shared data absent: " << kShared << " (../shared/data of the project)";
  const std::string dir = make_set();
  std::ofstream(dir + "/ball_truth.csv", std::ios::app)
      << "10,left_10.jpg,right_10.jpg,1599.5,1125.5,1469.5,1122.0,117.0,112.0,3.5,1.06,\n";
  auto set = rs::open_set(dir);
  ASSERT_FALSE(set.ok());
  EXPECT_NE(set.error().find("ball_truth.csv:5:"), std::string::npos) << set.error();
  EXPECT_NE(set.error().find("left_10.jpg"), std::string::npos) << set.error();
}

TEST(DetectorConfig, GivenAnOverrideFileAndFlagsWhenComposedThenTheyApplyOverTheShippedFile) {
  // Given an override file with two keys and the diameter flag
  const std::string dir = stereoball::testing::temp_dir();
  std::ofstream(dir + "/over.yaml") << "ball:\n  diameter_m: 0.30\np2p:\n  min_score: 0.5\n";
  rs::DetectorOverrides o;
  o.config_file = dir + "/over.yaml";
  o.no_floor_check = true;
  o.image_limit = cv::Size(2304, 1296);
  const std::string shipped = std::string(SB_SOURCE_DIR) + "/config/ball_detector.yaml";
  // When composed
  auto c = rs::compose_detector_config(shipped, o);
  ASSERT_TRUE(c.ok()) << c.error();
  // Then the file's keys, the flags and the shipped rest are all in force
  EXPECT_DOUBLE_EQ(c->params.ball_diameter_m, 0.30);
  EXPECT_DOUBLE_EQ(c->params.floor_tolerance_m, 0.0);
  EXPECT_EQ(c->params.max_image_size(), cv::Size(2304, 1296));
  EXPECT_EQ(c->changes.size(), 3u);
  // And every value of the file that differs from the shipped one is listed, dotted
  EXPECT_EQ(c->changed_keys,
            (std::vector<std::string>{"ball.diameter_m: 0.30", "p2p.min_score: 0.5"}));
  // And a value equal to the shipped one is not a change
  std::ofstream(dir + "/same.yaml") << "ball:\n  diameter_m: 0.22\n";
  o.config_file = dir + "/same.yaml";
  c = rs::compose_detector_config(shipped, o);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_TRUE(c->changed_keys.empty());
  o.config_file = dir + "/over.yaml";
  // And the flag wins over the file
  o.ball_diameter_m = 0.24;
  c = rs::compose_detector_config(shipped, o);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_DOUBLE_EQ(c->params.ball_diameter_m, 0.24);
  // And the snapshot allowance sets the detector's skew
  o.snapshot_skew_ns = 16'700'000;
  c = rs::compose_detector_config(shipped, o);
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->params.epipolar_skew_ns, 16'700'000);
  // And a key the detector does not know is refused, named
  std::ofstream(dir + "/typo.yaml") << "ball:\n  diameter: 0.30\n";
  o.config_file = dir + "/typo.yaml";
  c = rs::compose_detector_config(shipped, o);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().find("ball.diameter"), std::string::npos) << c.error();
}
