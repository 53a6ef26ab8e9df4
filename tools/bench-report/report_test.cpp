// The report's rendering: header facts, exact commands, verbatim output, "not run" entries.
#include "report.hpp"

#include <gtest/gtest.h>

namespace br = stereoball::bench_report;

namespace {

br::MachineInfo machine() {
  br::MachineInfo m;
  m.cpu_model = "Test CPU 3000";
  m.cores = 2;
  m.load = "1.00 0.50 0.25";
  m.date_utc = "2026-12-05 18:00 UTC";
  m.commit = "abc123";
  m.report_command = "stereoball bench report --only tracking";
  return m;
}

}  // namespace

TEST(BenchTable, EveryEntryHasANameProgramAndDataAndNamesAreUnique) {
  // Given the bench table
  const auto& table = br::bench_table();
  // Then every entry can be run and described, and names identify entries
  ASSERT_FALSE(table.empty());
  for (const auto& e : table) {
    EXPECT_FALSE(e.name.empty());
    EXPECT_EQ(e.program.rfind("stereoball-", 0), 0u) << e.name;
    EXPECT_FALSE(e.measures.empty()) << e.name;
    EXPECT_FALSE(e.data.empty()) << e.name;
    EXPECT_EQ(br::find_bench(e.name), &e);
  }
  EXPECT_EQ(br::find_bench("no-such-bench"), nullptr);
}

TEST(BenchTable, UserCommandIsTheStereoballSubcommandWithItsArguments) {
  // Given the built-in tracking entry
  const br::BenchEntry* e = br::find_bench("tracking");
  ASSERT_NE(e, nullptr);
  // When its command is rendered
  // Then it is what a user types
  EXPECT_EQ(br::user_command(*e), "stereoball bench tracking --drive controller");
  // And a tool outside `bench` keeps its own subcommand
  const br::BenchEntry* render = br::find_bench("render");
  ASSERT_NE(render, nullptr);
  EXPECT_EQ(br::user_command(*render), "stereoball sim-bench --frames 300");
}

TEST(RenderReport, HeaderNamesMachineDateCommitAndTheReportCommand) {
  // Given one bench that ran
  br::BenchOutcome o;
  o.entry = br::find_bench("tracking");
  o.state = br::BenchOutcome::State::kRan;
  o.command = "stereoball bench tracking --drive controller";
  o.date_utc = "2026-12-05 18:05 UTC";
  o.load = "3.00 2.00 1.00";
  o.output = "accepted 98.38 %\n";
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then the header and the bench's exact command and output are in it
  EXPECT_NE(md.find("Test CPU 3000, 2 logical cores"), std::string::npos);
  EXPECT_NE(md.find("2026-12-05 18:00 UTC"), std::string::npos);
  EXPECT_NE(md.find("`abc123`"), std::string::npos);
  EXPECT_NE(md.find("`stereoball bench report --only tracking`"), std::string::npos);
  EXPECT_NE(md.find("Command (2026-12-05 18:05 UTC, load average 3.00 2.00 1.00):\n\n```sh\n"
                    "stereoball bench tracking --drive controller\n```"),
            std::string::npos);
  EXPECT_NE(md.find("```text\naccepted 98.38 %\n```"), std::string::npos);
}

TEST(RenderReport, ABenchNotRunSaysSoWithItsCommandAndNoFigures) {
  // Given a bench that did not run
  br::BenchOutcome o;
  o.entry = br::find_bench("closed-loop");
  o.reason = "slow";
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then it says "Not run" with the reason and the command, and prints no output block
  EXPECT_NE(md.find("**Not run** for this report (slow)"), std::string::npos);
  EXPECT_NE(md.find(br::user_command(*o.entry)), std::string::npos);
  EXPECT_EQ(md.find("```text"), std::string::npos);
}

TEST(RenderReport, OutputWithBackticksCannotCloseItsBlock) {
  // Given output that contains a Markdown fence
  br::BenchOutcome o;
  o.entry = br::find_bench("detect");
  o.state = br::BenchOutcome::State::kRan;
  o.command = "x";
  o.output = "```\nline";
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then the block uses a longer fence and the output ends with a newline
  EXPECT_NE(md.find("````text\n```\nline\n````"), std::string::npos);
}

TEST(RenderReport, OutputReadFromJsonIsShownAsJson) {
  // Given a bench whose only saved output is its --json file
  br::BenchOutcome o;
  o.entry = br::find_bench("closed-loop");
  o.state = br::BenchOutcome::State::kRan;
  o.command = "stereoball bench closed-loop --jobs 2 --json closed-loop.json";
  o.output = "{\"total\": 0.95}\n";
  o.output_is_json = true;
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then the JSON is printed as JSON under its command
  EXPECT_NE(md.find("```json\n{\"total\": 0.95}\n```"), std::string::npos);
}

TEST(RenderReport, ABenchRunAtAnotherCommitNamesIt) {
  // Given a saved output from another commit than the report's
  br::BenchOutcome o;
  o.entry = br::find_bench("stereo");
  o.state = br::BenchOutcome::State::kRan;
  o.command = "stereoball bench stereo";
  o.date_utc = "2026-12-05 17:00 UTC";
  o.commit = "0123456789ab";
  o.output = "x\n";
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then its command line names that commit
  EXPECT_NE(md.find("Command (2026-12-05 17:00 UTC, commit 0123456789ab):"), std::string::npos);
}

TEST(RenderReport, ABenchRunOnAnotherMachineNamesItAndOneRunHereDoesNot) {
  // Given a saved output from another machine and one from the report's machine
  br::BenchOutcome elsewhere;
  elsewhere.entry = br::find_bench("stereo");
  elsewhere.state = br::BenchOutcome::State::kRan;
  elsewhere.command = "stereoball bench stereo";
  elsewhere.date_utc = "2026-12-05 17:00 UTC";
  elsewhere.machine = "Other CPU 9000, 2 logical cores";
  elsewhere.output = "x\n";
  br::BenchOutcome here = elsewhere;
  here.entry = br::find_bench("auth");
  here.command = "stereoball bench auth";
  here.machine = br::machine_text(machine());
  // When the report is rendered
  const std::string md = br::render_report(machine(), {elsewhere, here});
  // Then only the first names its machine; the header names the report's
  EXPECT_NE(md.find("Command (2026-12-05 17:00 UTC, on Other CPU 9000, 2 logical cores):"),
            std::string::npos);
  EXPECT_NE(md.find("Command (2026-12-05 17:00 UTC):"), std::string::npos);
  EXPECT_NE(md.find("| machine | Test CPU 3000, 2 logical cores |"), std::string::npos);
}

TEST(RenderReport, AFailedBenchSaysWhy) {
  // Given a bench that exited with an error
  br::BenchOutcome o;
  o.entry = br::find_bench("latency");
  o.state = br::BenchOutcome::State::kFailed;
  o.command = "stereoball bench latency --runs 1";
  o.reason = "exit status 2";
  // When the report is rendered
  const std::string md = br::render_report(machine(), {o});
  // Then the failure and its reason are stated
  EXPECT_NE(md.find("**Failed**: exit status 2"), std::string::npos);
}

TEST(RenderReport, ARunningOrIncompleteBenchIsNeverListedAsRanAndShowsNoFigures) {
  for (const auto state :
       {br::BenchOutcome::State::kRunning, br::BenchOutcome::State::kIncomplete}) {
    // Given a bench still running, or one stopped part way
    br::BenchOutcome o;
    o.entry = br::find_bench("closed-loop");
    o.state = state;
    o.reason = "started 08:30 UTC";
    // When the report is rendered
    const std::string md = br::render_report(machine(), {o});
    // Then its row and section say so, with its command and no output block
    const std::string name(br::state_name(state));
    EXPECT_NE(md.find("` | " + name + " |"), std::string::npos) << md;
    EXPECT_EQ(md.find("| ran"), std::string::npos);
    EXPECT_NE(
        md.find(state == br::BenchOutcome::State::kRunning ? "**Running**" : "**Incomplete**"),
        std::string::npos);
    EXPECT_NE(md.find(br::user_command(*o.entry)), std::string::npos);
    EXPECT_EQ(md.find("```text"), std::string::npos);
  }
}
