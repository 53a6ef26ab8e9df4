// The project's documents: every benchmark figure they quote is in the generated
// docs/benchmarks.md, relative links lead to files that exist, the `stereoball` commands and
// flags they show exist, no dated diary lines, and the user documents stay short.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
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

// Every `stereoball-*` program the tree builds, with the folder of the CMakeLists.txt that
// adds it (`stereoball A B` runs stereoball-A-B if it exists, else stereoball-A).
std::map<std::string, fs::path> programs() {
  static const std::regex kExecutable("add_executable\\(\\s*(stereoball-[A-Za-z0-9_-]+)");
  std::map<std::string, fs::path> found;
  for (const char* dir : {"components", "tools", "tests"}) {
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir)) {
      if (e.path().filename() != "CMakeLists.txt") continue;
      const std::string text = read(e.path());
      for (auto it = std::sregex_iterator(text.begin(), text.end(), kExecutable);
           it != std::sregex_iterator(); ++it)
        found[(*it)[1].str()] = e.path().parent_path();
    }
  }
  return found;
}

// The C++ sources of a folder and below.
std::string sources_below(const fs::path& dir) {
  std::string all;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const auto ext = e.path().extension();
    if (e.is_regular_file() && (ext == ".cpp" || ext == ".hpp")) all += read(e.path());
  }
  return all;
}

// The flag helpers several programs share (common_flags.cpp, frame_codec_flags.cpp,
// live_flags.cpp, loop_cli.cpp, ...): every *flags*.cpp and *cli*.cpp of the tree.
std::string shared_flag_sources() {
  std::string all;
  for (const char* dir : {"components", "tools"}) {
    for (const auto& e : fs::recursive_directory_iterator(kRoot / dir)) {
      const std::string name = e.path().filename().string();
      if (e.path().extension() == ".cpp" &&
          (name.find("flags") != std::string::npos || name.find("cli") != std::string::npos))
        all += read(e.path());
    }
  }
  return all;
}

// Whether text holds flag as a whole flag (not only a longer one that starts alike).
bool has_flag(const std::string& text, const std::string& flag) {
  for (auto at = text.find(flag); at != std::string::npos; at = text.find(flag, at + 1)) {
    const std::size_t end = at + flag.size();
    if (end == text.size() ||
        !(std::islower(static_cast<unsigned char>(text[end])) ||
          std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '-'))
      return true;
  }
  return false;
}

// The code a document shows: each inline `span` (which may wrap lines) and each line of a
// fenced block (backslash continuations joined), with the line it starts on.
std::vector<std::pair<std::string, int>> code_of(const std::string& text) {
  std::vector<std::pair<std::string, int>> code;
  std::istringstream in(text);
  bool fence = false;
  std::string prose, pending;
  std::vector<int> prose_lines;  // line number of each character of prose
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (line.find("```") != std::string::npos) {
      fence = !fence;
      continue;
    }
    if (fence) {
      if (!line.empty() && line.back() == '\\') {
        pending += line.substr(0, line.size() - 1) + " ";
        continue;
      }
      code.emplace_back(pending + line, n);
      pending.clear();
      continue;
    }
    prose += line + " ";
    prose_lines.resize(prose.size(), n);
  }
  for (std::size_t open = prose.find('`'); open != std::string::npos;) {
    const std::size_t close = prose.find('`', open + 1);
    if (close == std::string::npos) break;
    code.emplace_back(prose.substr(open + 1, close - open - 1), prose_lines[open]);
    open = prose.find('`', close + 1);
  }
  return code;
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

TEST(Documents, TheStereoballCommandsAndFlagsTheyShowExist) {
  // Given every program the tree builds and the code the documents show
  const auto built = programs();
  const std::string shared_flags = shared_flag_sources();
  std::map<std::string, std::string> sources;  // program -> its folder's sources
  static const std::regex kCommand("(^|[\\s(/])stereoball ([a-z][a-z0-9-]*)([^`]*)");
  static const std::regex kWord("^[a-z][a-z0-9-]*$");
  std::string problems;
  int flags_checked = 0;
  for (const auto& doc : documents()) {
    for (const auto& [code, n] : code_of(read(doc))) {
      for (auto it = std::sregex_iterator(code.begin(), code.end(), kCommand);
           it != std::sregex_iterator(); ++it) {
        std::string first = (*it)[2].str();
        if (first == "help" || first == "version") continue;
        if (first == "foxglove") first = "view";
        // The words after the command, up to the end of the shell command
        std::vector<std::string> words;
        std::istringstream rest((*it)[3].str());
        for (std::string w; rest >> w;) {
          if (w == "|" || w == "\\|" || w == "||" || w == "&&" || w == ";" || w[0] == '#') break;
          words.push_back(w);
        }
        // When the program it runs is looked up
        std::string program = "stereoball-" + first;
        if (!words.empty() && std::regex_match(words[0], kWord) &&
            built.count(program + "-" + words[0]))
          program += "-" + words[0];
        const std::string where = fs::relative(doc, kRoot).string() + ":" + std::to_string(n);
        if (!built.count(program)) {
          problems += where + ": no program runs `stereoball " + first + "`\n";
          continue;
        }
        if (!sources.count(program)) sources[program] = sources_below(built.at(program));
        // and each flag is looked up in its sources and the shared flag helpers
        for (std::string w : words) {
          if (w.rfind("--", 0) != 0 || w.size() < 3 ||
              !std::isalpha(static_cast<unsigned char>(w[2])))
            continue;
          w = w.substr(0, w.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789-", 2));
          if (w == "--help") continue;
          ++flags_checked;
          if (!has_flag(sources[program], w) && !has_flag(shared_flags, w))
            problems += where + ": " + program + " has no flag " + w + "\n";
        }
      }
    }
  }
  // Then every command names a program and every flag is one of that program's
  EXPECT_GT(flags_checked, 20) << "the documents show almost no flags: is the search broken?";
  EXPECT_TRUE(problems.empty()) << "commands or flags the programs lack:\n" << problems;
}

TEST(Documents, EveryCommandOfTheReadmeTableIsInStereoballsHelp) {
  // Given the commands README.md's table lists and those `stereoball help` prints
  const std::string readme = read(kRoot / "README.md");
  const std::string dispatcher = read(kRoot / "tools" / "stereoball" / "main.cpp");
  static const std::regex kRow("\\n\\| `stereoball ([a-z][a-z0-9-]*)");
  std::string missing;
  int rows = 0;
  for (auto it = std::sregex_iterator(readme.begin(), readme.end(), kRow);
       it != std::sregex_iterator(); ++it) {
    ++rows;
    // When each is looked up in the dispatcher's list of commands
    if (dispatcher.find("{\"" + (*it)[1].str() + "\", ") == std::string::npos)
      missing += (*it)[1].str() + "\n";
  }
  // Then the help lists every one of them
  EXPECT_GT(rows, 10) << "README.md's command table was not found";
  EXPECT_TRUE(missing.empty()) << "README.md lists commands `stereoball help` does not:\n"
                               << missing;
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
