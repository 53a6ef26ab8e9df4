// main() of every sb_add_gtest binary: GoogleTest's, plus an exit code that tells ctest what
// happened. 0: every case that ran passed; 1: a case failed; 77 (ctest's SKIP_RETURN_CODE):
// every case that ran skipped, with one "SKIP: Suite.Case: reason" line each. A run where some
// cases passed and others skipped fails: one ctest entry must not report cases it did not run
// as passed, nor hide the ones that passed behind a skip. Cases that can skip get their own
// ctest entry (sb_add_gtest ... SKIPPABLE suffix filter).
// In a grouped test executable (SB_TEST_GROUPS, cmake/StereoBall.cmake) each ctest entry passes
// --sb_sources=FILE,FILE,... (paths relative to the source root): only the cases defined in
// those files run, further narrowed by --gtest_filter. A list that names no case is an error.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

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

// True when name matches glob (GoogleTest's filter patterns: '*' any text, '?' one character).
bool glob_matches(const char* glob, const char* name) {
  if (*glob == '\0') return *name == '\0';
  if (*glob == '*')
    return glob_matches(glob + 1, name) || (*name != '\0' && glob_matches(glob, name + 1));
  if (*name == '\0') return false;
  return (*glob == '?' || *glob == *name) && glob_matches(glob + 1, name + 1);
}

// True when name matches one of the ':'-separated patterns.
bool any_matches(std::string_view patterns, const std::string& name) {
  while (true) {
    const size_t end = patterns.find(':');
    const std::string one(patterns.substr(0, end));
    if (glob_matches(one.c_str(), name.c_str())) return true;
    if (end == std::string_view::npos) return false;
    patterns.remove_prefix(end + 1);
  }
}

// True when name passes a --gtest_filter value ("POSITIVE[-NEGATIVE]").
bool passes_filter(const std::string& filter, const std::string& name) {
  const size_t dash = filter.find('-');
  const std::string positive = filter.substr(0, dash);
  const bool in = positive.empty() ? true : any_matches(positive, name);
  return in && (dash == std::string::npos ||
                !any_matches(std::string_view(filter).substr(dash + 1), name));
}

// True when path (as the compiler recorded it) is the file rel, a path below the source root.
bool is_file(const char* path, const std::string& rel) {
  const std::string_view p(path);
  return p.size() >= rel.size() && p.substr(p.size() - rel.size()) == rel &&
         (p.size() == rel.size() || p[p.size() - rel.size() - 1] == '/');
}

// --sb_sources=A,B: sets the filter to the cases defined in those files that pass the filter
// given. Returns false (with a message) when the files define no case at all.
bool restrict_to_sources(const std::string& list) {
  std::vector<std::string> files;
  size_t start = 0;
  while (start <= list.size()) {
    const size_t end = std::min(list.find(',', start), list.size());
    if (end > start) files.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  const std::string given = GTEST_FLAG_GET(filter);
  const ::testing::UnitTest& unit = *::testing::UnitTest::GetInstance();
  std::string chosen;
  int defined = 0;
  for (int s = 0; s < unit.total_test_suite_count(); ++s) {
    const ::testing::TestSuite& suite = *unit.GetTestSuite(s);
    for (int t = 0; t < suite.total_test_count(); ++t) {
      const ::testing::TestInfo& info = *suite.GetTestInfo(t);
      bool mine = false;
      for (const std::string& f : files) mine = mine || is_file(info.file(), f);
      if (!mine) continue;
      ++defined;
      const std::string name = std::string(suite.name()) + "." + info.name();
      if (!passes_filter(given, name)) continue;
      chosen += (chosen.empty() ? "" : ":") + name;
    }
  }
  if (defined == 0) {
    std::printf("FAILED: --sb_sources=%s names no file that defines a test case here\n",
                list.c_str());
    return false;
  }
  GTEST_FLAG_SET(filter, chosen.empty() ? std::string("-*") : chosen);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  constexpr const char kSources[] = "--sb_sources=";
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], kSources, sizeof kSources - 1) != 0) continue;
    if (!restrict_to_sources(argv[i] + sizeof kSources - 1)) return 1;
  }
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
