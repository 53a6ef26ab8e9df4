// The project's documents: every benchmark figure they quote is in the generated
// docs/benchmarks.md, relative links lead to files that exist, no dated diary lines, and the
// user documents stay short.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "doc_figures.hpp"

namespace br = stereoball::bench_report;
namespace fs = std::filesystem;

namespace {

const fs::path kRoot = SB_SOURCE_DIR;

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// README.md, DEVELOPERS.md, every README.md under components/ and tools/, deploy/README.md and
// docs/*.md except the generated benchmarks.md.
std::vector<fs::path> documents() {
  std::vector<fs::path> docs{kRoot / "README.md", kRoot / "DEVELOPERS.md",
                             kRoot / "deploy" / "README.md"};
  for (const char* dir : {"components", "tools"}) {
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir)) {
      if (e.is_regular_file() && e.path().filename() == "README.md") docs.push_back(e.path());
    }
  }
  if (fs::exists(kRoot / "docs")) {
    for (const auto& e : fs::directory_iterator(kRoot / "docs")) {
      if (e.path().extension() == ".md" && e.path().filename() != "benchmarks.md")
        docs.push_back(e.path());
    }
  }
  std::sort(docs.begin(), docs.end());
  return docs;
}

int line_count(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

// Calls visit(line, line number) for each line of doc outside fenced code.
template <typename Visit>
void for_each_prose_line(const fs::path& doc, Visit visit) {
  std::istringstream in(read(doc));
  bool fence = false;
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.find("```") != std::string::npos) fence = !fence;
    if (!fence) visit(line, n);
  }
}

}  // namespace

TEST(Documents, EveryQuotedBenchmarkFigureIsInTheGeneratedReport) {
  // Given the generated report
  const fs::path report_path = kRoot / "docs" / "benchmarks.md";
  ASSERT_TRUE(fs::exists(report_path)) << "run `stereoball bench report` to generate it";
  const std::string report = read(report_path);
  // When every document's figures are looked up in it
  std::string problems;
  for (const auto& doc : documents()) {
    for (const auto& f : br::figures_missing_from(read(doc), report)) {
      problems += fs::relative(doc, kRoot).string() + ":" + std::to_string(f.line) + ": \"" +
                  f.text + "\"\n";
    }
  }
  // Then none is missing (link to docs/benchmarks.md instead of typing a figure)
  EXPECT_TRUE(problems.empty()) << "figures not in docs/benchmarks.md:\n" << problems;
}

TEST(Documents, RelativeLinksLeadToExistingFiles) {
  // Given every document's Markdown links outside code
  static const std::regex kLink("\\]\\(([^)\\s]+)\\)");
  std::string problems;
  for (const auto& doc : documents()) {
    for_each_prose_line(doc, [&](const std::string& line, int n) {
      for (auto it = std::sregex_iterator(line.begin(), line.end(), kLink);
           it != std::sregex_iterator(); ++it) {
        std::string target = (*it)[1].str();
        if (target.rfind("http", 0) == 0 || target.rfind("mailto:", 0) == 0 || target[0] == '#')
          continue;
        target = target.substr(0, target.find('#'));
        // When a link is resolved against the document's folder
        if (!fs::exists(doc.parent_path() / target))
          problems +=
              fs::relative(doc, kRoot).string() + ":" + std::to_string(n) + ": " + target + "\n";
      }
    });
  }
  // Then it exists
  EXPECT_TRUE(problems.empty()) << "broken links:\n" << problems;
}

TEST(Documents, NoDatedDiaryLines) {
  // Given the documents (history lives in CHANGELOG.md)
  static const std::regex kDate("\\b20[0-9]{2}-[01][0-9]-[0-3][0-9]\\b");
  std::string problems;
  for (const auto& doc : documents()) {
    for_each_prose_line(doc, [&](const std::string& line, int n) {
      // When a line outside code carries a date
      if (std::regex_search(line, kDate))
        problems += fs::relative(doc, kRoot).string() + ":" + std::to_string(n) + "\n";
    });
  }
  // Then there is none
  EXPECT_TRUE(problems.empty()) << "dated lines (move them to CHANGELOG.md):\n" << problems;
}

TEST(Documents, UserDocumentsStayShort) {
  // Given README.md and the component and tool READMEs
  // Then README.md has at most 250 lines and each of the others at most 400
  EXPECT_LE(line_count(read(kRoot / "README.md")), 250);
  for (const auto& doc : documents()) {
    const std::string rel = fs::relative(doc, kRoot).string();
    if (rel.rfind("components/", 0) == 0 || rel.rfind("tools/", 0) == 0) {
      EXPECT_LE(line_count(read(doc)), 400) << rel;
    }
  }
}
