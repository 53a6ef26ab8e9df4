// Benchmark figures quoted in Markdown documents, and whether the generated report holds them.
//
// A benchmark figure is a number with a fractional part (98.38, 0.6, 5.8), or a range of two
// numbers (289-352, 98.31-98.35), written in the prose of a document and directly followed (one
// space allowed) by a unit that only a measurement produces: `%`, `ms`, `µs`, `us`, `x` (a
// speed ratio), `fps`, `MB/s`, `Mbit/s`; or an F1 score (`F1 0.811`). Prose is everything outside
// fenced code blocks, inline code spans, HTML comments, link targets and the generated parameter
// tables (between `<!-- params:begin -->` and `<!-- params:end -->`). Whole numbers (`200 ms`, `10
// %`) are settings and limits, not figures; a setting with a fraction is written as code
// (`deadline_s: 0.2`).
#pragma once

#include <string>
#include <vector>

namespace stereoball::bench_report {

// One figure found in a document.
struct DocFigure {
  int line = 0;                      // 1-based line in the document
  std::string text;                  // as written, e.g. "98.38 %" or "289-352 ms"
  std::vector<std::string> numbers;  // the number(s) alone, e.g. {"98.38"} or {"289", "352"}
};

// Every benchmark figure in the prose of a Markdown document.
std::vector<DocFigure> find_figures(const std::string& markdown);

// True when NUMBER appears in TEXT as a whole number (not part of a longer one).
bool report_holds(const std::string& text, const std::string& number);

// The figures of MARKDOWN one of whose numbers REPORT does not hold.
std::vector<DocFigure> figures_missing_from(const std::string& markdown, const std::string& report);

}  // namespace stereoball::bench_report
