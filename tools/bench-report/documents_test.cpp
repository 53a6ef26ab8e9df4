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

// README.md, DEVELOPERS.md, every README.md under components/, tools/ and tests/data/, those
// of tests/'s folders, deploy/README.md and docs/*.md except the generated benchmarks.md.
std::vector<fs::path> documents() {
  std::vector<fs::path> docs{kRoot / "README.md", kRoot / "DEVELOPERS.md",
                             kRoot / "deploy" / "README.md"};
  for (const auto& dir : {kRoot / "components", kRoot / "tools", kRoot / "tests" / "data"}) {
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
      if (e.is_regular_file() && e.path().filename() == "README.md") docs.push_back(e.path());
    }
  }
  // One level only under tests/: a test's folder may hold installed npm packages.
  for (const auto& e : fs::directory_iterator(kRoot / "tests")) {
    if (e.path().filename() != "data" && fs::is_regular_file(e.path() / "README.md"))
      docs.push_back(e.path() / "README.md");
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

// Whether doc is a data set's README (tests/data/**).
bool is_data_readme(const fs::path& doc) {
  const std::string rel = fs::relative(doc, kRoot).generic_string();
  return rel.rfind("tests/data/", 0) == 0;
}

// text with the sections on how a data set's labels were made blanked, line numbers kept: a
// heading "How ... labelled", down to the next heading of its level or above. Their figures
// (the share of rays a snap kept, a fit's RMS, the zoom a circle was checked at) describe the
// committed label files, measured once when they were made; no code change moves them, so
// they are facts of the data set like its licence and counts, not benchmark figures.
std::string without_labelling_notes(const std::string& text) {
  std::istringstream in(text);
  std::string out;
  bool fence = false;
  std::size_t blanking_level = 0;  // 0: not in such a section
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("```", 0) == 0) fence = !fence;
    const std::size_t level = fence ? 0 : line.find_first_not_of('#');
    const bool heading = level != 0 && level != std::string::npos && line[level] == ' ';
    if (heading && blanking_level != 0 && level <= blanking_level) blanking_level = 0;
    if (heading && blanking_level == 0 && line.compare(level, 5, " How ") == 0 &&
        line.find("labelled") != std::string::npos)
      blanking_level = level;
    out += (blanking_level != 0 ? "" : line) + "\n";
  }
  return out;
}

// The component READMEs: components/*/README.md.
std::vector<fs::path> component_readmes() {
  std::vector<fs::path> found;
  for (const auto& e : fs::directory_iterator(kRoot / "components")) {
    if (e.is_directory() && fs::is_regular_file(e.path() / "README.md"))
      found.push_back(e.path() / "README.md");
  }
  std::sort(found.begin(), found.end());
  return found;
}

// Whether a component declares a field table of its own: one of its headers declares an
// accessor returning `params::FieldTable<Type>&`, as DEVELOPERS.md's recipe has it.
bool declares_field_table(const fs::path& component) {
  static const std::regex kAccessor("FieldTable<[A-Z][A-Za-z0-9_]+>&\\s+[a-z0-9_]+\\(\\)");
  for (const auto& e : fs::recursive_directory_iterator(component)) {
    if (e.path().extension() == ".hpp" && std::regex_search(read(e.path()), kAccessor)) return true;
  }
  return false;
}

// Whether text holds the generated parameter table's two markers, each on a line of its own.
bool has_params_markers(const std::string& text) {
  return text.find("\n<!-- params:begin -->\n") != std::string::npos &&
         text.find("\n<!-- params:end -->\n") != std::string::npos;
}

// Whether a README that doc links to (relative link, resolved from its folder) holds the
// generated parameter table.
bool links_to_params_table(const fs::path& doc) {
  static const std::regex kReadmeLink("\\]\\(([^)\\s#]*README\\.md)(#[^)\\s]*)?\\)");
  const std::string text = read(doc);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), kReadmeLink);
       it != std::sregex_iterator(); ++it) {
    const fs::path target = doc.parent_path() / (*it)[1].str();
    if (fs::is_regular_file(target) && has_params_markers(read(target))) return true;
  }
  return false;
}

// The parts a reader expects of a component README that text lacks: a first paragraph (what
// the component does) right under the `# name` title, a `## Parameters` section, a `## Limits`
// section, and where the component declares a field table (field_table) the generated table,
// in text itself or in a README it links to (table_linked).
std::vector<std::string> missing_readme_parts(const std::string& text, bool field_table,
                                              bool table_linked) {
  std::vector<std::string> missing;
  std::istringstream in(text);
  std::string line, first_paragraph;
  bool fence = false, parameters = false, limits = false;
  const bool titled = std::getline(in, line) && line.rfind("# ", 0) == 0;
  while (std::getline(in, line)) {
    if (first_paragraph.empty() && !line.empty()) first_paragraph = line;
    if (line.rfind("```", 0) == 0) fence = !fence;
    if (fence) continue;
    if (line.rfind("## Parameters", 0) == 0) parameters = true;
    if (line.find_last_not_of(' ') == 8 && line.rfind("## Limits", 0) == 0) limits = true;
  }
  if (!titled) missing.push_back("a first line `# name`");
  const bool prose = !first_paragraph.empty() &&
                     std::string("#|`<-").find(first_paragraph[0]) == std::string::npos;
  if (!prose) missing.push_back("a first paragraph saying what it does");
  if (!parameters) missing.push_back("a `## Parameters` section");
  if (!limits) missing.push_back("a `## Limits` section");
  if (field_table && !has_params_markers(text) && !table_linked)
    missing.push_back("the generated parameter table (`<!-- params:begin -->`/`end`)");
  return missing;
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
    const std::string text = is_data_readme(doc) ? without_labelling_notes(read(doc)) : read(doc);
    for (const auto& f : br::figures_missing_from(text, report)) {
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
  static const std::regex kCodeSpan("`[^`]*`");
  std::string problems;
  for (const auto& doc : documents()) {
    for_each_prose_line(doc, [&](const std::string& line, int n) {
      // When a line outside code (fenced or a `span`: a file name may hold a date) carries one
      if (std::regex_search(std::regex_replace(line, kCodeSpan, " "), kDate))
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

TEST(Documents, ALabellingSectionOfADataReadmeIsLeftOutOfTheFigureCheck) {
  // Given a data README with a figure in its labelling notes and one in a later section
  const std::string text =
      "# A set labelled by hand\n\nKept 76-84% of the rays.\n## How it was labelled\nKept 76-84% "
      "of the rays.\n"
      "### One image\nsnap 15-65%\n```\n# not a heading\n```\n## First run\n12.5 ms\n";
  // When the labelling notes are blanked
  const std::string kept = without_labelling_notes(text);
  // Then only those lines go: the figures before and after them are still checked
  const auto figures = br::find_figures(kept);
  ASSERT_EQ(figures.size(), 2u) << kept;
  EXPECT_EQ(figures[0].line, 3);
  EXPECT_EQ(figures[1].line, 12);
}

TEST(Documents, AComponentReadmeLackingAPartIsNamed) {
  // Given a README with every part, and copies each lacking one
  const std::string whole =
      "# c\n\nDoes one thing.\n\n## How\nSo.\n## Parameters\n<!-- params:begin -->\n|k|\n"
      "<!-- params:end -->\n\n## Limits\n- Only one.\n";
  const auto without = [&](const std::string& part) {
    std::string text = whole;
    return text.erase(text.find(part), part.size());
  };
  // When their missing parts are listed
  // Then the whole one lacks nothing, and each copy lacks exactly what was taken out
  EXPECT_TRUE(missing_readme_parts(whole, true, false).empty());
  const auto no_limits = missing_readme_parts(without("## Limits\n"), false, false);
  ASSERT_EQ(no_limits.size(), 1u);
  EXPECT_NE(no_limits[0].find("Limits"), std::string::npos);
  const auto no_table = missing_readme_parts(without("<!-- params:end -->\n"), true, false);
  ASSERT_EQ(no_table.size(), 1u);
  EXPECT_NE(no_table[0].find("params:begin"), std::string::npos);
  EXPECT_TRUE(missing_readme_parts(without("<!-- params:end -->\n"), true, true).empty());
  EXPECT_TRUE(missing_readme_parts(without("<!-- params:end -->\n"), false, false).empty());
  EXPECT_EQ(missing_readme_parts(without("Does one thing.\n"), false, false).size(), 1u);
  EXPECT_EQ(missing_readme_parts(without("## Parameters\n"), false, false).size(), 1u);
}

TEST(Documents, EveryComponentReadmeSaysWhatHowParametersAndLimits) {
  // Given each components/*/README.md and whether its component declares a field table
  const auto readmes = component_readmes();
  ASSERT_GT(readmes.size(), 8u) << "the component READMEs were not found";
  std::string problems;
  for (const auto& readme : readmes) {
    const bool field_table = declares_field_table(readme.parent_path());
    // When the parts a reader expects are looked for
    for (const auto& part :
         missing_readme_parts(read(readme), field_table, links_to_params_table(readme)))
      problems += fs::relative(readme, kRoot).string() + " lacks " + part + "\n";
  }
  // Then none is missing (the table: tools/update_params_tables.sh, never by hand)
  EXPECT_TRUE(problems.empty()) << problems;
}
