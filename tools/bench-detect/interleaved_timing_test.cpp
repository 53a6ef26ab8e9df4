// The bench's interleaved timing on a fake clock: the order methods run in, which runs are
// timed, the medians and the ratio with its spread (logic only; nothing here is timed).

#include "interleaved_timing.hpp"

#include <gtest/gtest.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace bdt = stereoball::bench_detect;

namespace {

// A clock that only moves when a fake method runs: cost(m, i, call) ms per call, where call
// counts the runs of (m, i) so far (0 = the warm-up). Every call is logged.
struct FakeTimedRuns {
  explicit FakeTimedRuns(std::function<double(int, int, int)> c) : cost(std::move(c)) {}
  std::function<double(int, int, int)> cost;
  double now_ms = 0.0;
  std::map<std::pair<int, int>, int> calls;
  std::vector<std::string> log;

  bdt::TimedMethods callbacks() {
    return {[this](int i) { log.push_back("start " + std::to_string(i)); },
            [this](int m, int i) {
              const int call = calls[{m, i}]++;
              now_ms += cost(m, i, call);
              log.push_back("run " + std::to_string(m) + "/" + std::to_string(i));
            }};
  }
  std::function<double()> clock() {
    return [this] { return now_ms; };
  }
};

}  // namespace

TEST(InterleavedTimingTest,
     GivenThreeMethods_WhenTimed_ThenEachImageRunsThemInTurnRotatingTheFirst) {
  FakeTimedRuns fake{[](int, int, int) { return 1.0; }};
  bdt::time_interleaved(3, 2, 3, fake.callbacks(), fake.clock());
  const std::vector<std::string> image0 = {"start 0", "run 0/0", "run 1/0", "run 2/0",  // warm-up
                                           "run 0/0", "run 1/0", "run 2/0",             // round 0
                                           "run 1/0", "run 2/0", "run 0/0",             // round 1
                                           "run 2/0", "run 0/0", "run 1/0"};            // round 2
  ASSERT_EQ(fake.log.size(), 2 * image0.size());
  EXPECT_EQ(std::vector<std::string>(fake.log.begin(), fake.log.begin() + 13), image0);
  EXPECT_EQ(fake.log[13], "start 1");
}

TEST(InterleavedTimingTest, GivenACostlyFirstCall_WhenTimed_ThenTheWarmUpIsNotCounted) {
  // Method m costs (m + 1) * (image + 1) ms, its first call on an image 1000 ms more.
  FakeTimedRuns fake{
      [](int m, int i, int call) { return (m + 1.0) * (i + 1.0) + (call == 0 ? 1000.0 : 0.0); }};
  const auto t = bdt::time_interleaved(2, 3, 3, fake.callbacks(), fake.clock());
  ASSERT_EQ(t.methods(), 2);
  ASSERT_EQ(t.images(), 3);
  ASSERT_EQ(t.rounds(), 3);
  EXPECT_EQ(t.per_image_ms(0), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_EQ(t.per_image_ms(1), (std::vector<double>{2.0, 4.0, 6.0}));
  EXPECT_DOUBLE_EQ(t.median_ms(0), 2.0);
  EXPECT_DOUBLE_EQ(t.median_ms(1), 4.0);
}

TEST(InterleavedTimingTest, GivenARoundWhereTheMachineIsBusy_WhenRatioTaken_ThenItIsUnchanged) {
  // Method 0 costs twice method 1; in the second timed round (call 2) both take 5 times longer.
  FakeTimedRuns fake{[](int m, int i, int call) {
    const double base = (m == 0 ? 2.0 : 1.0) * (1.0 + i);
    return call == 2 ? 5.0 * base : base;
  }};
  const auto t = bdt::time_interleaved(2, 4, 3, fake.callbacks(), fake.clock());
  const bdt::TimeRatio r = bdt::time_ratio(t, 0, 1);
  EXPECT_DOUBLE_EQ(r.ratio, 2.0);
  EXPECT_DOUBLE_EQ(r.round_min, 2.0);
  EXPECT_DOUBLE_EQ(r.round_max, 2.0);
  EXPECT_DOUBLE_EQ(r.image_p25, 2.0);
  EXPECT_DOUBLE_EQ(r.image_p75, 2.0);
  EXPECT_DOUBLE_EQ(t.round_median_ms(0, 1), 5.0 * t.round_median_ms(0, 0));
}

TEST(InterleavedTimingTest,
     GivenRatiosThatDifferPerImage_WhenRatioTaken_ThenQuartilesShowTheSpread) {
  // Method 1 costs 10 ms everywhere; method 0 costs 5, 10, 15, 20, 25 ms on images 0-4.
  FakeTimedRuns fake{[](int m, int i, int) { return m == 1 ? 10.0 : 5.0 * (i + 1); }};
  const auto t = bdt::time_interleaved(2, 5, 1, fake.callbacks(), fake.clock());
  const bdt::TimeRatio r = bdt::time_ratio(t, 0, 1);
  EXPECT_DOUBLE_EQ(r.ratio, 1.5);
  EXPECT_DOUBLE_EQ(r.image_p25, 1.0);
  EXPECT_DOUBLE_EQ(r.image_p75, 2.0);
  EXPECT_EQ(bdt::format_ratio(r), "1.50 (rounds 1.50-1.50, per image p25-p75 1.00-2.00)");
}

TEST(InterleavedTimingTest, GivenNoImage_WhenRatioTaken_ThenItIsZeroAndNothingRuns) {
  FakeTimedRuns fake{[](int, int, int) { return 1.0; }};
  const auto t = bdt::time_interleaved(2, 0, 3, fake.callbacks(), fake.clock());
  EXPECT_TRUE(fake.log.empty());
  const bdt::TimeRatio r = bdt::time_ratio(t, 0, 1);
  EXPECT_EQ(r.ratio, 0.0);
  EXPECT_EQ(t.rounds(), 0);
}

TEST(InterleavedTimingTest, GivenAnEvenCount_WhenMedianTaken_ThenItIsTheUpperMiddle) {
  EXPECT_EQ(bdt::upper_median({4.0, 1.0, 3.0, 2.0}), 3.0);
  EXPECT_EQ(bdt::upper_median({}), 0.0);
}
