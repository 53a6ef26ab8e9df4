// Runs the real stereoball-calibrate binary on OpenCV's sample pairs and on bad inputs.

#include "stereo/io/calibration_file.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <string>

namespace {

namespace fs = std::filesystem;
const std::string kData = std::string(SB_SHARED_DATA_DIR) + "/opencv-samples";

struct ToolRun {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

std::string slurp(const fs::path& p) {
  std::string s;
  if (FILE* f = std::fopen(p.c_str(), "r")) {
    std::array<char, 4096> buf{};
    std::size_t n = 0;
    while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0) s.append(buf.data(), n);
    std::fclose(f);
  }
  return s;
}

class CalibrateToolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sb_calibrate_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  ToolRun run(const std::string& args) {
    const std::string cmd = std::string(SB_BIN_DIR) + "/stereoball-calibrate " + args + " >" +
                            (dir_ / "out.txt").string() + " 2>" + (dir_ / "err.txt").string();
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir_ / "out.txt"),
            slurp(dir_ / "err.txt")};
  }
  fs::path dir_;
};

TEST_F(CalibrateToolTest, GivenSampleListWhenCalibratedThenFileMeetsTargetsAndReportPrinted) {
  // Given OpenCV's stereo_calib.xml list, When calibrated with 25 mm squares
  const std::string out = (dir_ / "calib.yaml").string();
  const ToolRun r =
      run("--pairs " + kData + "/stereo_calib.xml --board 9x6 --square-mm 25 -o " + out);
  // Then it succeeds, reports RMS / row error / per-pair errors, and the file loads
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("RMS reprojection error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rectified row error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("left14.jpg + right14.jpg"), std::string::npos) << r.out;
  const auto calib = stereoball::stereo::load_calibration(out);
  ASSERT_TRUE(calib.ok()) << calib.error();
  EXPECT_LT(calib->rms_px, 0.5);
  EXPECT_GE(calib->per_pair_rms_px.size(), 10u);
  EXPECT_EQ(calib->image_size, cv::Size(640, 480));
}

TEST_F(CalibrateToolTest, GivenGlobsWithABoardlessPairWhenCalibratedThenPairSkippedAndListed) {
  // Given eight sample pairs plus one blank pair, as globs
  for (int i = 1; i <= 8; ++i) {
    // (std::format is not in GCC 12; to_string + literal trips a -Wrestrict false positive)
    std::string n = std::to_string(i);
    n.insert(0, 1, '0');
    n.append(".jpg");
    fs::create_symlink(kData + "/left" + n, dir_ / ("left" + n));
    fs::create_symlink(kData + "/right" + n, dir_ / ("right" + n));
  }
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  cv::imwrite((dir_ / "left99.png").string(), blank);
  cv::imwrite((dir_ / "right99.png").string(), blank);
  // When calibrated
  const ToolRun r = run("--left-glob '" + (dir_ / "left*").string() + "' --right-glob '" +
                        (dir_ / "right*").string() + "' -o " + (dir_ / "c.yaml").string());
  // Then the blank pair is listed as skipped and the rest calibrate
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("skip left99.png + right99.png: board not found in left image"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("pairs used:                 8"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(dir_ / "c.yaml"));
}

TEST_F(CalibrateToolTest, GivenSimulatedFreeRunningSequenceWhenCalibratedThenStillPosesTaken) {
  // Given the simulator's calibration scene, 6 drawn poses, the right eye 15 ms late, written
  // at 10 Hz with each eye's capture stamp
  std::FILE* f = std::fopen((dir_ / "scene.yaml").c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs(
      "name: scene\ncalibration:\n  eye_skew_ms: 15\n  random_poses: {count: 6, seed: 3, "
      "hold_s: 0.6, move_s: 0.3}\n",
      f);
  std::fclose(f);
  const std::string seq = (dir_ / "seq").string();
  const std::string sim = std::string(SB_BIN_DIR) + "/stereoball-sim --config " + SB_SOURCE_DIR +
                          "/config/simulator.yaml --scenario " + (dir_ / "scene.yaml").string() +
                          " --every 3 --png-dir " + seq + " >/dev/null";
  ASSERT_EQ(std::system(sim.c_str()), 0);
  // When calibrated from the sequence
  const ToolRun r = run("--sequence " + seq + "/frames.csv --board 9x6 --square-mm 30 -o " +
                        (dir_ / "c.yaml").string());
  // Then one pose per hold is taken and the baseline is the true one within 0.5 %
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("6 still poses taken"), std::string::npos) << r.out;
  const auto est = stereoball::stereo::load_calibration((dir_ / "c.yaml").string());
  const auto truth = stereoball::stereo::load_calibration(seq + "/calibration.yaml");
  ASSERT_TRUE(est.ok() && truth.ok());
  EXPECT_NEAR(cv::norm(est->t), cv::norm(truth->t), 0.005 * cv::norm(truth->t));
}

TEST_F(CalibrateToolTest, GivenBadSequenceFileThenLineNamedAndNothingWritten) {
  // Given a sequence whose second frame has a stamp that is not a number
  std::FILE* f = std::fopen((dir_ / "frames.csv").c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fputs("left,right,left_stamp_ns,right_stamp_ns\nl0.png,r0.png,0,0\nl1.png,r1.png,1e9,5\n",
             f);
  std::fclose(f);
  // When calibrated from it
  const ToolRun r =
      run("--sequence " + (dir_ / "frames.csv").string() + " -o " + (dir_ / "c.yaml").string());
  // Then it fails naming the file and line, and writes nothing
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("frames.csv line 3"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "c.yaml"));
}

// Links the 13 sample pairs into dir as left/rightNN.jpg.
void link_samples(const fs::path& dir) {
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    std::string n = std::to_string(i);
    if (i < 10) n.insert(0, 1, '0');
    n.append(".jpg");
    fs::create_symlink(kData + "/left" + n, dir / ("left" + n));
    fs::create_symlink(kData + "/right" + n, dir / ("right" + n));
  }
}

TEST_F(CalibrateToolTest, GivenRightViewsTakenAfterTheBoardMovedWhenCalibratedThenThoseDropped) {
  // Given the sample pairs where two right shots show the board 3 px lower (an unsynchronised
  // rig: the board moved between the left and the right shot)
  link_samples(dir_);
  for (const char* id : {"04", "11"}) {
    const fs::path right = dir_ / ("right" + std::string(id) + ".jpg");
    const cv::Mat image = cv::imread(right.string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty());
    cv::Mat moved;
    cv::warpAffine(image, moved, cv::Matx23d(1, 0, 0, 0, 1, 3), image.size(), cv::INTER_LINEAR,
                   cv::BORDER_REPLICATE);
    fs::remove(right);
    ASSERT_TRUE(cv::imwrite((dir_ / ("right" + std::string(id) + ".png")).string(), moved));
  }
  // When calibrated
  const ToolRun r = run("--left-glob '" + (dir_ / "left*").string() + "' --right-glob '" +
                        (dir_ / "right*").string() + "' -o " + (dir_ / "c.yaml").string());
  // Then both are dropped with the reason, the rest is used, and the figures before and after
  // are printed
  ASSERT_EQ(r.exit_code, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("dropped 2 inconsistent pair(s)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("drop left04.jpg + right04.png: stereo error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("drop left11.jpg + right11.png: stereo error"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("with every pair:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("pairs used:                 11"), std::string::npos) << r.out;
  const auto calib = stereoball::stereo::load_calibration((dir_ / "c.yaml").string());
  ASSERT_TRUE(calib.ok()) << calib.error();
  EXPECT_LT(calib->rms_px, 0.3);
}

TEST_F(CalibrateToolTest, GivenSwappedCamerasWhenCalibratedThenFailsSayingHowToFix) {
  // Given the sample pairs with the left and right globs exchanged
  link_samples(dir_);
  // When calibrated
  const ToolRun r = run("--left-glob '" + (dir_ / "right*").string() + "' --right-glob '" +
                        (dir_ / "left*").string() + "' -o " + (dir_ / "c.yaml").string());
  // Then it fails with one line naming the negative baseline and the fix, and writes nothing
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("negative baseline"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("swap --left-glob and --right-glob"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_FALSE(fs::exists(dir_ / "c.yaml"));
}

TEST_F(CalibrateToolTest, GivenTooFewBoardsWhenCalibratedThenOneLineErrorAndNoFile) {
  const ToolRun r =
      run("--pairs " + kData + "/stereo_calib.xml --min-pairs 20 -o " + (dir_ / "c.yaml").string());
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("need at least 20 (--min-pairs)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1);
  EXPECT_FALSE(fs::exists(dir_ / "c.yaml"));
}

TEST_F(CalibrateToolTest, GivenBadFlagsWhenRunThenClearErrorNamingFlag) {
  const std::string list = "--pairs " + kData + "/stereo_calib.xml -o x.yaml";
  const ToolRun board = run(list + " --board 9by6");
  EXPECT_NE(board.exit_code, 0);
  EXPECT_NE(board.err.find("--board '9by6'"), std::string::npos) << board.err;
  const ToolRun square = run(list + " --square-mm -3");
  EXPECT_NE(square.exit_code, 0);
  EXPECT_NE(square.err.find("square_m"), std::string::npos) << square.err;
  const ToolRun none = run("-o x.yaml");
  EXPECT_NE(none.exit_code, 0);
  EXPECT_NE(none.err.find("--pairs"), std::string::npos) << none.err;
  const ToolRun globs = run("--left-glob '" + kData + "/left0*.jpg' --right-glob '" + kData +
                            "/right1*.jpg' -o x.yaml");
  EXPECT_NE(globs.exit_code, 0);
  EXPECT_NE(globs.err.find("--right-glob matches 4"), std::string::npos) << globs.err;
}

}  // namespace
