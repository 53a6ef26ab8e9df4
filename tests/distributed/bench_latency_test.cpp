// Smoke test of stereoball bench latency: a short one-host run of the real system writes the
// end-to-end figures under the keys the issue names, finite and ordered.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <fstream>

#include "process.hpp"

namespace st = stereoball::testing;
using namespace std::chrono_literals;

TEST(BenchLatency, GivenAShortOneHostRun_ThenJsonHasFiniteOrderedEndToEndFigures) {
  // Given the whole system on one host, raw frames at 30 Hz, measured for 4 s
  const std::string json_path = st::temp_dir() + "/latency.json";
  const auto [code, out] =
      st::run({st::bin("stereoball-bench-latency"), "--encoding", "raw", "--rate", "30",
               "--seconds", "3", "--warmup", "5", "--json", json_path},
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
