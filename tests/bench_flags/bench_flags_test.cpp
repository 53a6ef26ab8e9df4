// The benches refuse a bad flag value at start: exit code, one message naming the flag, and
// nothing of the benchmark's output (each run has a deadline far below any sweep's length).

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "process.hpp"

namespace st = stereoball::testing;
using namespace std::chrono_literals;

namespace {

struct BenchRun {
  int code;
  std::string out;
};

// The bench with args; 30 s is far below any sweep (minutes) but ample for a refusal.
BenchRun run_bench(const std::string& program, const std::vector<std::string>& args) {
  std::vector<std::string> argv{st::bin(program)};
  argv.insert(argv.end(), args.begin(), args.end());
  auto [code, out] = st::run(argv, 30s);
  return {code, out};
}

bool has(const std::string& out, const std::string& text) {
  return out.find(text) != std::string::npos;
}

}  // namespace

TEST(BenchDetectFlags, GivenATimeCapThatNamesNoMethodWhenStartedThenRefusedBeforeTheSweep) {
  // Given a --time-cap that is not a method of the table (a prefix of one)
  // When the bench starts
  const auto r = run_bench("stereoball-bench-detect", {"--time-cap", "HOUGH"});
  // Then it exits non-zero at once, names the flag and the methods it takes, and ran nothing
  ASSERT_NE(r.code, -1) << "still running at the deadline: the sweep ran\n" << r.out;
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_TRUE(has(r.out, "--time-cap")) << r.out;
  EXPECT_TRUE(has(r.out, "EDCircles")) << r.out;
  EXPECT_FALSE(has(r.out, "Synthetic suite")) << r.out;
}

TEST(BenchDetectFlags, GivenEachMethodOfTheTableWhenParsedThenTheTimeCapIsAccepted) {
  // Given every name --time-cap takes, and --help after it so nothing runs
  for (const std::string method :
       {"", "p2p paper rule", "HOUGH_GRADIENT", "HOUGH_GRADIENT_ALT", "EDCircles"}) {
    // When parsed
    const auto r = run_bench("stereoball-bench-detect", {"--time-cap", method, "--help"});
    // Then it is accepted (the help is printed, exit 0)
    EXPECT_EQ(r.code, 0) << "'" << method << "': " << r.out;
    EXPECT_TRUE(has(r.out, "--time-cap")) << r.out;
  }
}

TEST(BenchDetectFlags, GivenAMissingLabelsFolderWhenStartedThenOneLineNamesIt) {
  const auto r = run_bench("stereoball-bench-detect", {"--labels-dir", "/nonexistent/sb-labels"});
  EXPECT_EQ(r.code, 1) << r.out;
  EXPECT_TRUE(has(r.out, "/nonexistent/sb-labels")) << r.out;
  EXPECT_FALSE(has(r.out, "Synthetic suite")) << r.out;
}

TEST(BenchDetectFlags, GivenAnOnlyThatMatchesNoMethodWhenStartedThenRefusedWithExitCode2) {
  const auto r = run_bench("stereoball-bench-detect", {"--only", "no-such-method"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "--only")) << r.out;
  EXPECT_FALSE(has(r.out, "Synthetic suite")) << r.out;
}

TEST(BenchRealStereoFlags, GivenAMalformedImageLimitWhenStartedThenRefusedNamingTheFlag) {
  const auto r = run_bench("stereoball-bench-real-stereo", {"--image-limit", "wide"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "--image-limit")) << r.out;
}

TEST(BenchRealStereoFlags, GivenASetFolderThatDoesNotExistWhenStartedThenRefusedNamingIt) {
  const auto r = run_bench("stereoball-bench-real-stereo", {"--set", "/nonexistent/sb-set"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "/nonexistent/sb-set")) << r.out;
}

TEST(BenchRealStereoFlags, GivenAnUnknownFrameEncodingWhenStartedThenRefusedNamingTheFlag) {
  const auto r = run_bench("stereoball-bench-real-stereo", {"--frame-encoding", "webp"});
  EXPECT_NE(r.code, 0) << r.out;
  EXPECT_NE(r.code, -1) << r.out;
  EXPECT_TRUE(has(r.out, "--frame-encoding")) << r.out;
}

TEST(BenchRealStereoFlags, GivenAReferenceWithoutInProcessWhenStartedThenRefusedNamingBoth) {
  const auto r = run_bench("stereoball-bench-real-stereo", {"--reference", "edcircles"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "--reference needs --in-process")) << r.out;
}

TEST(BenchRealStereoFlags, GivenAnUnknownReferenceMethodWhenStartedThenRefusedListingTheKnown) {
  const auto r =
      run_bench("stereoball-bench-real-stereo", {"--in-process", "--reference", "no-such"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "'no-such'")) << r.out;
  EXPECT_TRUE(has(r.out, "edcircles")) << r.out;
}

TEST(BenchReportFlags, GivenAnOnlyThatNamesNoBenchWhenStartedThenRefusedBeforeAnyBenchRuns) {
  const std::string dir = st::temp_dir();
  const auto r = run_bench(
      "stereoball-bench-report",
      {"--only", "no-such-bench", "--outputs", dir + "/outputs", "--out", dir + "/benchmarks.md"});
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_TRUE(has(r.out, "no bench named 'no-such-bench'")) << r.out;
  EXPECT_FALSE(has(r.out, "running")) << r.out;
}
