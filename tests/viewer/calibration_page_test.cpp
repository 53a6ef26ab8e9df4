// The calibration page in a real browser (headless Chromium) against the simulator's
// calibration scene, all real processes on this test's DDS domain: `stereoball calibrate live`
// starts the page (stereoball view --calibrate), the simulator carries a board through poses
// in front of its true rig, and the page shows both eyes with the corners drawn, takes poses,
// gives a passing verdict and writes the calibration when its button is pressed. The file is
// compared with the rig the simulator publishes (its truth).

#include <signal.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>

#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "simulator/core/simulator.hpp"
#include "simulator/io/scenario_file.hpp"
#include "simulator/io/sim_params_file.hpp"
#include "stereo/core/board_calibration.hpp"
#include "stereo/io/calibration_file.hpp"
#include "stereo/msg/calibration_msg.hpp"
#include "stereoball/topics.hpp"
#include "viewer_test_support.hpp"

namespace stereoball::testing {
namespace {

using namespace std::chrono_literals;
namespace fs = std::filesystem;

// A short calibration scene: a 9x6 board of 30 mm squares through 20 poses, each held 1 s,
// seen by free-running eyes (the right one captures 15 ms after the left): the still-board
// rule must keep moving boards out.
std::string write_scenario(const std::string& dir) {
  const std::string path = dir + "/calibration_page.yaml";
  std::ofstream(path) << "name: calibration_page\n"
                         "seed: 5\n"
                         "calibration:\n"
                         "  board: {inner_corners: [9, 6], square_m: 0.03, margin_m: 0.03}\n"
                         "  eye_skew_ms: 15\n"
                         "  random_poses: {count: 20, seed: 1, near_m: 0.45, far_m: 1.5, "
                         "max_tilt_deg: 40, max_roll_deg: 17, hold_s: 1.0, move_s: 0.4}\n";
  return path;
}

// The calibration the simulator publishes: its true rig.
std::optional<stereo::StereoCalibration> true_rig(const std::string& partition) {
  dds::DomainParticipant p({test_domain(), partition});
  dds::DataReader<stereoball_msg_StereoCalibration> reader(p, topics::kStereoCalibration);
  std::optional<stereo::StereoCalibration> out;
  eventually(
      [&] {
        for (auto& s : reader.take(4))
          if (auto c = stereo::calibration_from_message(*s)) out = std::move(c).value();
        return out.has_value();
      },
      20s);
  return out;
}

// Mean rectified row error of calib on the exact projections of the scene's board corners
// (noise-free matched points of the true rig), pixels; -1 when the scene cannot be built.
double row_error_on_truth(const stereo::StereoCalibration& calib, const std::string& scenario) {
  const auto params = simulator::load_sim_params(source_path("config/simulator.yaml"));
  const auto scene = simulator::load_scenario(scenario);
  if (!params || !scene) return -1;
  const simulator::Simulator sim(*params, *scene);
  const auto& board = *sim.calibration_scene();
  std::vector<stereo::PairCorners> pairs;
  for (const auto& hold : board.holds) {
    stereo::PairCorners pc;
    for (const auto& p : board_corners_px(sim.rig(), simulator::Eye::kLeft, board.board, hold.pose))
      pc.left_px.emplace_back(p);
    for (const auto& p :
         board_corners_px(sim.rig(), simulator::Eye::kRight, board.board, hold.pose))
      pc.right_px.emplace_back(p);
    pairs.push_back(std::move(pc));
  }
  return stereo::rectified_row_error_px(calib, pairs).first;
}

double pct(double got, double truth) {
  return 100.0 * std::abs(got - truth) / std::abs(truth);
}

TEST(CalibrationPage, TheBrowserShowsCornersTakesPosesAndWritesAPassingCalibration) {
  if (chromium_binary().empty())
    GTEST_SKIP() << "Chromium is not installed (Debian package `chromium`; run.sh installs it)";
  if (node_binary().empty() || npm_dir().empty())
    GTEST_SKIP() << "node or the tests' npm packages are missing (SB_VIEWER_NPM_DIR)";
  // Given the calibration page started as a user does, on a free port
  const std::string partition = unique_partition();
  const std::string out = test_out_dir("calibration_page");
  const std::string written = out + "/rig.yaml";
  auto page =
      Process::start({bin("stereoball-calibrate-live"), "--domain", std::to_string(test_domain()),
                      "--partition", partition, "--port", "0", "--board", "9x6", "--square-mm",
                      "30", "--poses", "10", "--still-s", "0.3", "-o", written});
  ASSERT_TRUE(page.wait_for_output("calibration page: http://", 30s)) << page.output();
  std::smatch m;
  const std::string log = page.output();
  ASSERT_TRUE(std::regex_search(log, m, std::regex("calibration page: (http://\\S+/calibrate)")));
  const std::string url = m[1];
  // and the simulator carrying the board in front of its rig
  const std::string scenario = write_scenario(out);
  auto sim = Process::start({bin("simulator"), "--domain", std::to_string(test_domain()),
                             "--partition", partition, "--scenario", scenario, "--loop"});
  // When Chromium shows the page and presses "write calibration" after the verdict
  const auto [rc, check] = run(
      {node_binary(), npm_dir() + "/calibrate_check.mjs", url, out, chromium_binary(), "75"}, 100s);
  // Then the page drew the corners, took poses, passed and wrote the file
  EXPECT_EQ(rc, 0) << check << "\n--- page:\n" << page.output() << "\n--- sim:\n" << sim.output();
  std::printf("%s", check.c_str());
  ASSERT_TRUE(fs::exists(written)) << page.output();
  EXPECT_TRUE(page.wait_for_output("calibration: wrote " + written, 5s)) << page.output();
  EXPECT_NE(page.output().find("calibration: pose 1 taken"), std::string::npos);
  // and the file agrees with the simulator's true rig
  const auto got = stereo::load_calibration(written);
  ASSERT_TRUE(got) << got.error();
  const auto truth = true_rig(partition);
  ASSERT_TRUE(truth.has_value()) << "the simulator published no calibration";
  const double focal =
      std::max(pct(got->k1(0, 0), truth->k1(0, 0)), pct(got->k2(1, 1), truth->k2(1, 1)));
  const double baseline = pct(stereo::baseline_m(*got), stereo::baseline_m(*truth));
  const double rows = row_error_on_truth(*got, scenario);
  std::printf(
      "against the simulator's rig: focal %.3f %%, baseline %.3f %% (%.4f m vs %.4f m), "
      "rectified row error on the true corners %.3f px\n",
      focal, baseline, stereo::baseline_m(*got), stereo::baseline_m(*truth), rows);
  EXPECT_LT(focal, 0.5);
  EXPECT_LT(baseline, 0.5);
  EXPECT_GE(rows, 0);
  EXPECT_LT(rows, 0.2);
  sim.signal(SIGINT);
  page.signal(SIGINT);
  EXPECT_TRUE(page.wait_for_exit(20s).has_value());
  EXPECT_TRUE(sim.wait_for_exit(20s).has_value());
}

}  // namespace
}  // namespace stereoball::testing
