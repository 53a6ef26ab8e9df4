// bench transport runs ddsperf as it runs its own ping-pong, and says what still differs.
#include "like_for_like.hpp"

#include <gtest/gtest.h>

#include <algorithm>

namespace bt = stereoball::bench_transport;

namespace {

bool has_run(const std::vector<std::string>& args, const std::vector<std::string>& run) {
  return std::search(args.begin(), args.end(), run.begin(), run.end()) != args.end();
}

bool any_line_has(const std::vector<std::string>& lines, const std::string& part) {
  return std::any_of(lines.begin(), lines.end(),
                     [&](const std::string& l) { return l.find(part) != std::string::npos; });
}

}  // namespace

TEST(DdsperfSetup, PingSendsOurSampleSizeWithOurReliabilityOneAtATimeInAWaitset) {
  // Given ours measured at 1843288 serialized bytes, best effort, on ddsperf's domain 78
  const bt::DdsperfSetup setup{78, true, 1843288, 4};
  // When ddsperf's command lines are made
  const auto ping = bt::ddsperf_ping_args(setup);
  const auto pong = bt::ddsperf_pong_args(setup);
  // Then ping sends that size with no rate (next ping on the echo), both best effort, waitset
  EXPECT_EQ(ping.front(), "ddsperf");
  EXPECT_TRUE(has_run(ping, {"-i", "78", "-u"}));
  EXPECT_TRUE(has_run(ping, {"ping", "size", "1843288", "waitset"}));
  EXPECT_TRUE(has_run(ping, {"-D", "4"}));
  EXPECT_TRUE(has_run(pong, {"-i", "78", "-u"}));
  EXPECT_TRUE(has_run(pong, {"pong", "waitset"}));
  // And a reliable run has no -u
  const auto reliable = bt::ddsperf_ping_args({78, false, 1843288, 4});
  EXPECT_EQ(std::find(reliable.begin(), reliable.end(), "-u"), reliable.end());
}

TEST(DdsperfSetup, TheEnvironmentCarriesOurCycloneConfigurationOnce) {
  // Given an environment that already names another configuration
  const std::vector<std::string> env{"PATH=/usr/bin", "CYCLONEDDS_URI=file:///other.xml"};
  // When ours is set for ddsperf
  const auto out = bt::with_cyclone_uri(env, "<CycloneDDS/>");
  // Then ours replaces it and the rest is kept
  EXPECT_EQ(out, (std::vector<std::string>{"PATH=/usr/bin", "CYCLONEDDS_URI=<CycloneDDS/>"}));
}

TEST(ComparisonNotes, SayWhatIsSharedAndEveryRemainingDifference) {
  // Given equal sample sizes, reliable, under the loopback configuration
  bt::ComparisonFacts facts;
  facts.our_sample_bytes = facts.ddsperf_sample_bytes = 1843288;
  facts.our_pixel_bytes = 1843200;
  facts.reliable = true;
  facts.config = "loopback-only (keyless)";
  // When the notes are made
  const auto notes = bt::comparison_notes(facts);
  // Then they state what is the same and what differs
  EXPECT_TRUE(any_line_has(notes, "same: 1843288 B serialized per sample on both sides"));
  EXPECT_TRUE(any_line_has(notes, "88 B of header"));
  EXPECT_TRUE(any_line_has(notes, "reliable keep-last-1"));
  EXPECT_TRUE(any_line_has(notes, "loopback-only (keyless)"));
  EXPECT_TRUE(any_line_has(notes, "differs: ours has two participants per process"));
  EXPECT_TRUE(any_line_has(notes, "differs: ours is the typed StereoFrame"));
  EXPECT_TRUE(any_line_has(notes, "differs: a ping not echoed"));
  EXPECT_FALSE(any_line_has(notes, "differs: sample size"));
}

TEST(ComparisonNotes, AnUnmeasuredOrUnequalSampleSizeIsADifference) {
  // Given our size not measured
  bt::ComparisonFacts facts;
  facts.ddsperf_sample_bytes = 1843200;
  // When the notes are made
  const auto notes = bt::comparison_notes(facts);
  // Then the sample size is listed as a difference
  EXPECT_TRUE(any_line_has(notes, "differs: sample size, ours not measured, ddsperf 1843200 B"));
}
