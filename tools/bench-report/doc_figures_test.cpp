// What counts as a benchmark figure in a document, and when the report holds it.
#include "doc_figures.hpp"

#include <gtest/gtest.h>

namespace br = stereoball::bench_report;

TEST(FindFigures, DecimalsWithMeasurementUnitsInProseAreFigures) {
  // Given prose with a percentage, a time, a ratio and an F1 score
  const std::string md =
      "Accepted 98.38 % of frames in 5.8 ms,\n3.9x faster, report F1 0.811, 12.5fps.\n";
  // When figures are looked for
  const auto f = br::find_figures(md);
  // Then all five are found with their lines and numbers
  ASSERT_EQ(f.size(), 5u);
  EXPECT_EQ(f[0].numbers, std::vector<std::string>{"98.38"});
  EXPECT_EQ(f[0].text, "98.38 %");
  EXPECT_EQ(f[0].line, 1);
  EXPECT_EQ(f[1].text, "5.8 ms");
  EXPECT_EQ(f[2].text, "3.9x");
  EXPECT_EQ(f[2].line, 2);
  EXPECT_EQ(f[3].text, "12.5fps");
  EXPECT_EQ(f[4].numbers, std::vector<std::string>{"0.811"});
}

TEST(FindFigures, RangesAreFiguresWithBothNumbers) {
  // Given measured ranges, whole and decimal
  const std::string md = "zero command after 289-352 ms, seeds 98.31 - 98.35 %, 40–61 % lost\n";
  // When figures are looked for
  const auto f = br::find_figures(md);
  // Then each range is one figure holding both ends
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(f[0].text, "289-352 ms");
  EXPECT_EQ(f[0].numbers, (std::vector<std::string>{"289", "352"}));
  EXPECT_EQ(f[1].numbers, (std::vector<std::string>{"98.31", "98.35"}));
  EXPECT_EQ(f[2].numbers, (std::vector<std::string>{"40", "61"}));
}

TEST(FindFigures, SettingsCodeTablesAndLinksAreNotFigures) {
  // Given whole-number settings, inline code, a fenced block, a params table and a link
  const std::string md =
      "Deadline 200 ms, 10 % of the radius, `stale_after_s: 0.5 ms` here.\n"
      "```\nbench printed 97.5 %\n```\n"
      "<!-- params:begin -->\n| a | 0.25 % |\n<!-- params:end -->\n"
      "See [the figures](docs/x_1.5x.md) and <!-- 2.5 ms -->.\n"
      "Version 1.2.3 ms-free, 0.5 s stale, 640x480 images.\n"
      "Targets <= 0.1 % and ≥ 98.5 %, p99 < 2.5 ms.\n";
  // When figures are looked for
  // Then none is found
  const auto f = br::find_figures(md);
  EXPECT_TRUE(f.empty()) << f.front().text;
}

TEST(ReportHolds, MatchesWholeNumbersOnly) {
  // Given a report text
  const std::string report = "accepted 98.38 % | time 5.80 ms | 12.5.\n";
  // Then whole numbers match, parts of longer numbers do not
  EXPECT_TRUE(br::report_holds(report, "98.38"));
  EXPECT_TRUE(br::report_holds(report, "12.5"));
  EXPECT_FALSE(br::report_holds(report, "8.38"));
  EXPECT_FALSE(br::report_holds(report, "5.8"));
  EXPECT_FALSE(br::report_holds(report, "98.3"));
}

TEST(FiguresMissingFrom, ListsOnlyFiguresTheReportLacks) {
  // Given a document quoting one figure the report has and one it does not
  const std::string doc = "Accepted 98.38 % (was 97.10 % before).\n";
  // When checked against the report
  const auto missing = br::figures_missing_from(doc, "accepted 98.38 | 1-2\n");
  // Then only the absent one is listed
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].text, "97.10 %");
  // And a range needs both of its ends in the report
  EXPECT_EQ(br::figures_missing_from("took 98.38-99.00 ms\n", "98.38\n").size(), 1u);
}
