// What the report makes of a bench's saved outputs: only a run that recorded its end gives
// figures; one still running or stopped part way says so.
#include "saved_outputs.hpp"

#include <gtest/gtest.h>
#include <stdlib.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace br = stereoball::bench_report;
namespace fs = std::filesystem;

namespace {

class SavedOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string pattern = (fs::temp_directory_path() / "sb_saved_outputs_XXXXXX").string();
    ASSERT_NE(mkdtemp(pattern.data()), nullptr);
    dir_ = pattern;
    entry_ = br::find_bench("tracking");
    ASSERT_NE(entry_, nullptr);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void write(const std::string& suffix, const std::string& text) const {
    std::ofstream(dir_ / (entry_->name + suffix)) << text;
  }
  // NAME.cmd as the report writes it when the bench has ended with STATUS.
  void write_end(const std::string& status) const {
    write(".cmd", "stereoball bench tracking --drive controller\n2026-12-06 08:00 UTC\n" + status +
                      "\n42.5\n1.00 0.50 0.25\nabc123\nTest CPU 3000, 2 logical cores\n");
  }
  br::BenchOutcome read(bool process_alive) const {
    return br::read_saved(*entry_, dir_,
                          [process_alive](long, const std::string&) { return process_alive; });
  }

  fs::path dir_;
  const br::BenchEntry* entry_ = nullptr;
};

}  // namespace

TEST_F(SavedOutputs, ARunThatRecordedItsEndGivesItsFigures) {
  // Given output and the record of a run that ended well
  write(".txt", "accepted 98.38 %\n");
  write_end("ok");
  // When the folder is read
  const br::BenchOutcome o = read(false);
  // Then the bench ran, with its output, command and duration
  EXPECT_EQ(o.state, br::BenchOutcome::State::kRan);
  EXPECT_EQ(o.output, "accepted 98.38 %\n");
  EXPECT_EQ(o.command, "stereoball bench tracking --drive controller");
  EXPECT_DOUBLE_EQ(o.seconds, 42.5);
  EXPECT_EQ(o.commit, "abc123");
  EXPECT_EQ(o.machine, "Test CPU 3000, 2 logical cores");
}

TEST_F(SavedOutputs, ABenchStillRunningIsRunningWithNoFigures) {
  // Given a run's marker whose process still runs, its partial output, and an older run's end
  write(".txt", "accepted 12.00 %\n");
  write_end("ok");
  write(".running", br::running_marker_text({4242, "stereoball-bench-tracking", "08:30 UTC"}));
  // When the folder is read
  const br::BenchOutcome o = read(true);
  // Then it is running, and the partial output is not taken for a result
  EXPECT_EQ(o.state, br::BenchOutcome::State::kRunning);
  EXPECT_TRUE(o.output.empty());
  EXPECT_NE(o.reason.find("4242"), std::string::npos) << o.reason;
  EXPECT_EQ(br::state_name(o.state), "running");
}

TEST_F(SavedOutputs, ARunWhoseProcessIsGoneWithoutARecordedEndIsIncomplete) {
  // Given a marker left behind by a run killed together with its report
  write(".txt", "accepted 12.00 %\n");
  write(".running", br::running_marker_text({4242, "stereoball-bench-tracking", "08:30 UTC"}));
  // When the folder is read, the process no longer running
  const br::BenchOutcome o = read(false);
  // Then it is incomplete, with no figures
  EXPECT_EQ(o.state, br::BenchOutcome::State::kIncomplete);
  EXPECT_TRUE(o.output.empty());
  EXPECT_NE(o.reason.find("partial"), std::string::npos) << o.reason;
}

TEST_F(SavedOutputs, OutputWithoutARecordOfItsEndIsIncomplete) {
  // Given output but no NAME.cmd (a run stopped before it wrote one)
  write(".txt", "accepted 12.00 %\n");
  // When the folder is read
  const br::BenchOutcome o = read(false);
  // Then it is incomplete rather than "ran"
  EXPECT_EQ(o.state, br::BenchOutcome::State::kIncomplete);
  EXPECT_TRUE(o.output.empty());
  EXPECT_NE(o.reason.find("tracking.cmd"), std::string::npos) << o.reason;
}

TEST_F(SavedOutputs, ARecordCutShortIsIncomplete) {
  // Given a NAME.cmd with only its first two lines
  write(".txt", "accepted 12.00 %\n");
  write(".cmd", "stereoball bench tracking --drive controller\n2026-12-06 08:00 UTC\n");
  // When the folder is read
  // Then the run is incomplete
  EXPECT_EQ(read(false).state, br::BenchOutcome::State::kIncomplete);
}

TEST_F(SavedOutputs, ARunStoppedAtTheTimeLimitOrByASignalIsIncomplete) {
  for (const std::string status : {"stopped after the 60 min time limit", "killed by signal 9"}) {
    // Given a run whose recorded end says it was cut short
    write(".txt", "accepted 12.00 %\n");
    write_end(status);
    // When the folder is read
    const br::BenchOutcome o = read(false);
    // Then it is incomplete, giving the reason and no figures
    EXPECT_EQ(o.state, br::BenchOutcome::State::kIncomplete) << status;
    EXPECT_EQ(o.reason, status);
    EXPECT_TRUE(o.output.empty());
  }
}

TEST_F(SavedOutputs, ABenchThatExitedWithAnErrorFailedAndKeepsItsOutput) {
  // Given a run that ended with exit status 2
  write(".txt", "partial table\n");
  write_end("exit status 2: no data");
  // When the folder is read
  const br::BenchOutcome o = read(false);
  // Then it failed, and what it printed is kept to show why
  EXPECT_EQ(o.state, br::BenchOutcome::State::kFailed);
  EXPECT_EQ(o.reason, "exit status 2: no data");
  EXPECT_EQ(o.output, "partial table\n");
}

TEST_F(SavedOutputs, NothingSavedIsNotRun) {
  // Given an empty folder
  // When it is read
  const br::BenchOutcome o = read(false);
  // Then the bench was not run
  EXPECT_EQ(o.state, br::BenchOutcome::State::kNotRun);
  EXPECT_EQ(o.reason, "no output saved");
}

TEST(RunningMarker, RoundTripsAndRefusesWhatIsNotOne) {
  // Given a marker's text
  const std::string text = br::running_marker_text({77, "stereoball-bench-stereo", "09:00 UTC"});
  // When it is parsed
  const auto m = br::parse_running_marker(text);
  // Then it gives back what was written, and text that is no marker gives nothing
  ASSERT_TRUE(m);
  EXPECT_EQ(m->pid, 77);
  EXPECT_EQ(m->program, "stereoball-bench-stereo");
  EXPECT_EQ(m->date_utc, "09:00 UTC");
  EXPECT_FALSE(br::parse_running_marker(""));
  EXPECT_FALSE(br::parse_running_marker("x77\nprog\n"));
  EXPECT_FALSE(br::parse_running_marker("77\n"));
}

TEST(RunningMarker, ThisProcessRunsAndAProgramOfAnotherNameDoesNot) {
  // Given this test's own process id and program name
  const std::string self = fs::read_symlink("/proc/self/exe").filename().string();
  // Then it is found running under its name, and not under another one
  EXPECT_TRUE(br::process_runs(getpid(), self));
  EXPECT_FALSE(br::process_runs(getpid(), "stereoball-bench-no-such"));
}
