// main() of every sb_add_gtest binary: GoogleTest's, plus an exit code that tells ctest what
// happened. 0: every case that ran passed; 1: a case failed; 77 (ctest's SKIP_RETURN_CODE):
// every case that ran skipped, with one "SKIP: Suite.Case: reason" line each. A run where some
// cases passed and others skipped fails: one ctest entry must not report cases it did not run
// as passed, nor hide the ones that passed behind a skip. Cases that can skip get their own
// ctest entry (sb_add_gtest ... SKIPPABLE suffix filter).

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

namespace {

constexpr int kSkipExitCode = 77;

// The message GTEST_SKIP() << ... gave, on one line.
std::string skip_reason(const ::testing::TestResult& result) {
  for (int i = 0; i < result.total_part_count(); ++i) {
    const ::testing::TestPartResult& part = result.GetTestPartResult(i);
    if (!part.skipped()) continue;
    std::string text = part.message();
    for (char& c : text) {
      if (c == '\n') c = ' ';
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    return text.empty() ? "(no reason given)" : text;
  }
  return "(no reason given)";
}

// Prints one line per skipped case; returns how many there were.
int print_skips(const ::testing::UnitTest& unit) {
  int skipped = 0;
  for (int s = 0; s < unit.total_test_suite_count(); ++s) {
    const ::testing::TestSuite& suite = *unit.GetTestSuite(s);
    for (int t = 0; t < suite.total_test_count(); ++t) {
      const ::testing::TestInfo& info = *suite.GetTestInfo(t);
      if (!info.should_run() || !info.result()->Skipped()) continue;
      std::printf("SKIP: %s.%s: %s\n", suite.name(), info.name(),
                  skip_reason(*info.result()).c_str());
      ++skipped;
    }
  }
  return skipped;
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int failed = RUN_ALL_TESTS();
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  if (failed != 0) return failed;
  if (print_skips(unit) == 0) return 0;
  if (unit.successful_test_count() > 0) {
    std::printf(
        "FAILED: %d case(s) passed and %d skipped in one ctest entry, which can only say one "
        "of the two: give the cases that can skip their own entry (sb_add_gtest SKIPPABLE, "
        "cmake/StereoBall.cmake)\n",
        unit.successful_test_count(), unit.skipped_test_count());
    return 1;
  }
  return kSkipExitCode;
}
