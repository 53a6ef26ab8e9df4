// Smoke test of stereoball bench latency: a short one-host run of the real system writes the
// end-to-end figures under the keys the issue names, finite and ordered.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "process.hpp"

namespace st = stereoball::testing;
using namespace std::chrono_literals;

namespace {

// ball/detection's DETECTION_FOUND and DETECTION_NO_CALIBRATION (idl/stereoball.idl).
constexpr int kFound = 0, kNoCalibration = 4;

// The detection_status column of the measured rows of a --frames-csv file.
std::vector<int> measured_statuses(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);  // header: capture_ns,seq,detection_status,...,measured
  std::vector<int> out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.size() == 10 && cells[9] == "1") out.push_back(std::stoi(cells[2]));
  }
  return out;
}

}  // namespace

TEST(BenchLatency, GivenAShortOneHostRun_ThenJsonHasFiniteOrderedEndToEndFigures) {
  // Given the whole system on one host, raw frames at 30 Hz, measured for 4 s
  const std::string dir = st::temp_dir();
  const std::string json_path = dir + "/latency.json";
  const auto [code, out] = st::run(
      {st::bin("stereoball-bench-latency"), "--encoding", "raw", "--rate", "30", "--seconds", "3",
       "--warmup", "5", "--json", json_path, "--frames-csv", dir + "/frames_"},
      90s);
  ASSERT_EQ(code, 0) << out;
  // Then the JSON holds one_host.raw_30hz.end_to_end_ms.{p50,p90,p99,max}
  std::ifstream in(json_path);
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << out;
  const auto& e2e = j.at("one_host").at("raw_30hz").at("end_to_end_ms");
  double previous = 0.0;
  for (const char* q : {"p50", "p90", "p99", "max"}) {
    ASSERT_TRUE(e2e.at(q).is_number()) << q;
    const double v = e2e.at(q).get<double>();
    // finite, positive (a command follows its frame's exposure), and in order
    EXPECT_TRUE(std::isfinite(v)) << q;
    EXPECT_GT(v, 0.0) << q;
    EXPECT_GE(v, previous) << q;
    previous = v;
  }
  // And commands answered frames (the stages were joined by the carried capture stamp; how
  // many depends on the load of the shared machine)
  EXPECT_GE(e2e.at("n").get<double>(), 1.0) << out;
  // And every program of the system has its CPU and run-queue wait per frame, the detector's
  // CPU more than none
  const auto& cpu = j.at("one_host").at("raw_30hz").at("cpu_per_frame");
  for (const char* program : {"simulator", "ball_detector", "tracker", "motion_controller"}) {
    ASSERT_TRUE(cpu.contains(program)) << program << "\n" << out;
    EXPECT_GE(cpu.at(program).at("runqueue_wait_ms").get<double>(), 0.0) << program;
  }
  EXPECT_GT(cpu.at("ball_detector").at("cpu_ms").get<double>(), 0.0) << out;
  // And without --detector-config the detector read the shipped file, nothing changed
  const auto& detector = j.at("detector_config");
  EXPECT_EQ(detector.at("base").get<std::string>(), st::source_path("config/ball_detector.yaml"));
  EXPECT_EQ(detector.at("file").get<std::string>(), "");
  EXPECT_TRUE(detector.at("changed").empty()) << detector.dump();
  // And it found the ball in measured frames (the rolling ball is in view)
  const auto statuses = measured_statuses(dir + "/frames_one_host_raw_30hz_run1.csv");
  EXPECT_NE(std::count(statuses.begin(), statuses.end(), kFound), 0) << out;
}

TEST(BenchLatency, GivenADetectorConfigUnderTheFrameSize_ThenNoFrameIsSearchedAndKeysRecorded) {
  // Given a detector configuration whose image limit is below the simulator's 640x480 frames
  // (the ball_detector of the default run answers within this window: the test above)
  const std::string dir = st::temp_dir();
  std::ofstream(dir + "/small.yaml") << "image_limit:\n  max_width_px: 320\n  max_height_px: 240\n";
  // When the bench runs with it
  const auto [code, out] =
      st::run({st::bin("stereoball-bench-latency"), "--encoding", "raw", "--rate", "30",
               "--seconds", "3", "--warmup", "5", "--detector-config", dir + "/small.yaml",
               "--json", dir + "/latency.json", "--frames-csv", dir + "/frames_"},
              90s);
  // Then the report names the base file and both changed values
  EXPECT_NE(out.find("detector configuration: " + st::source_path("config/ball_detector.yaml")),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("image_limit.max_width_px: 320"), std::string::npos) << out;
  EXPECT_NE(out.find("image_limit.max_height_px: 240"), std::string::npos) << out;
  // And the detector refused the rig's 640x480 calibration over its limit: no measured frame
  // was searched (the shipped limit finds the ball: the test above)
  const auto statuses = measured_statuses(dir + "/frames_one_host_raw_30hz_run1.csv");
  ASSERT_FALSE(statuses.empty()) << out;
  EXPECT_EQ(std::count(statuses.begin(), statuses.end(), kNoCalibration),
            static_cast<std::ptrdiff_t>(statuses.size()))
      << out;
  // And the JSON records the file and the changed values
  std::ifstream in(dir + "/latency.json");
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  ASSERT_FALSE(j.is_discarded()) << out;
  EXPECT_EQ(j.at("detector_config").at("file").get<std::string>(), dir + "/small.yaml");
  EXPECT_EQ(j.at("detector_config").at("changed"),
            nlohmann::json({"image_limit.max_width_px: 320", "image_limit.max_height_px: 240"}));
  EXPECT_EQ(code, 0) << out;
}

TEST(BenchLatency, GivenABadDetectorConfig_ThenRefusedBeforeAnyRunNamingTheFileOrKey) {
  const std::string dir = st::temp_dir();
  std::ofstream(dir + "/typo.yaml") << "ball:\n  diameter: 0.30\n";
  std::ofstream(dir + "/broken.yaml") << "ball:\n  diameter_m: [0.30\n";
  const std::vector<std::pair<std::string, std::string>> cases{
      {"/nonexistent/ball_detector.yaml", "/nonexistent/ball_detector.yaml"},
      {dir + "/typo.yaml", "ball.diameter"},
      {dir + "/broken.yaml", dir + "/broken.yaml"}};
  for (const auto& [file, named] : cases) {
    // Given a missing file, an unknown key, a file that is not YAML
    // When the bench is started with it
    const auto [code, out] =
        st::run({st::bin("stereoball-bench-latency"), "--detector-config", file}, 20s);
    // Then it stops at once (exit 2, no run) naming the file or the key
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find(named), std::string::npos) << out;
    EXPECT_EQ(out.find("median of"), std::string::npos) << out;
  }
}

TEST(BenchLatency, GivenFramesCsvInAMissingFolder_ThenRefusedBeforeAnyRunNamingIt) {
  // Given a --frames-csv prefix whose folder does not exist
  const auto [code, out] = st::run(
      {st::bin("stereoball-bench-latency"), "--frames-csv", "/nonexistent/sb_frames_"}, 20s);
  // Then it stops at once with one line naming the folder (no run was started)
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("/nonexistent"), std::string::npos) << out;
  EXPECT_EQ(out.find("median of"), std::string::npos) << out;
}
