#include "doc_figures.hpp"

#include <regex>
#include <sstream>

namespace stereoball::bench_report {
namespace {

// Blanks what is not prose on one line: inline code spans, HTML comments, link targets.
std::string prose_of(const std::string& line) {
  std::string out = line;
  static const std::regex kCode("`[^`]*`");
  static const std::regex kComment("<!--.*?-->");
  static const std::regex kLinkTarget("\\]\\([^)]*\\)");
  out = std::regex_replace(out, kCode, " ");
  out = std::regex_replace(out, kComment, " ");
  out = std::regex_replace(out, kLinkTarget, "] ");
  return out;
}

// True when the prose before position AT ends with a comparison (a target or bound, "<= 5 ms").
bool after_comparison(const std::string& prose, std::size_t at) {
  std::string before = prose.substr(0, at);
  while (!before.empty() && before.back() == ' ') before.pop_back();
  for (const char* op : {"<", ">", "≤", "≥", "<=", ">="}) {
    const std::string o = op;
    if (before.size() >= o.size() && before.compare(before.size() - o.size(), o.size(), o) == 0)
      return true;
  }
  return false;
}

}  // namespace

std::vector<DocFigure> find_figures(const std::string& markdown) {
  // A number with a fraction or a range of numbers, not inside a longer token, then a unit.
  static const std::regex kFigure(
      "(^|[^0-9A-Za-z.])(([0-9]+(\\.[0-9]+)?) ?(-|–) ?)?([0-9]+(\\.[0-9]+)?)( ?)"
      "(%|ms\\b|µs|us\\b|x\\b|fps\\b|MB/s|Mbit/s)");
  static const std::regex kF1("\\bF1( score)?( of)? ([01]\\.[0-9]+)");
  std::vector<DocFigure> found;
  std::istringstream in(markdown);
  std::string line;
  int number = 0;
  bool in_fence = false, in_params = false, in_comment = false;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t");
    const std::string trimmed = first == std::string::npos ? "" : line.substr(first);
    if (trimmed.rfind("```", 0) == 0 || trimmed.rfind("~~~", 0) == 0) {
      in_fence = !in_fence;
      continue;
    }
    if (trimmed == "<!-- params:begin -->") in_params = true;
    if (trimmed == "<!-- params:end -->") in_params = false;
    if (in_fence || in_params) continue;
    std::string text = line;
    if (in_comment) {
      const auto end = text.find("-->");
      if (end == std::string::npos) continue;
      text = text.substr(end + 3);
      in_comment = false;
    }
    const auto open = text.rfind("<!--");
    if (open != std::string::npos && text.find("-->", open) == std::string::npos) {
      text = text.substr(0, open);
      in_comment = true;
    }
    const std::string prose = prose_of(text);
    for (auto it = std::sregex_iterator(prose.begin(), prose.end(), kFigure);
         it != std::sregex_iterator(); ++it) {
      const auto& m = *it;
      const bool range = m[2].matched;
      if (!range && !m[7].matched) continue;  // one whole number: a setting
      const auto first = static_cast<std::size_t>(m.position(0) + m[1].length());
      if (after_comparison(prose, first)) continue;  // a target: "<= 0.5 %"
      DocFigure f{number, m.str().substr(m[1].length()), {}};
      if (range) f.numbers.push_back(m[3].str());
      f.numbers.push_back(m[6].str());
      found.push_back(std::move(f));
    }
    for (auto it = std::sregex_iterator(prose.begin(), prose.end(), kF1);
         it != std::sregex_iterator(); ++it) {
      found.push_back({number, (*it)[0].str(), {(*it)[3].str()}});
    }
  }
  return found;
}

bool report_holds(const std::string& text, const std::string& number) {
  auto is_num = [](char c) { return (c >= '0' && c <= '9') || c == '.'; };
  for (auto at = text.find(number); at != std::string::npos; at = text.find(number, at + 1)) {
    const bool left_ok = at == 0 || !is_num(text[at - 1]);
    const std::size_t end = at + number.size();
    // A trailing full stop ends a sentence; a dot followed by a digit continues the number.
    const bool right_ok = end >= text.size() || !is_num(text[end]) ||
                          (text[end] == '.' && (end + 1 >= text.size() ||
                                                !(text[end + 1] >= '0' && text[end + 1] <= '9')));
    if (left_ok && right_ok) return true;
  }
  return false;
}

std::vector<DocFigure> figures_missing_from(const std::string& markdown,
                                            const std::string& report) {
  std::vector<DocFigure> missing;
  for (auto& f : find_figures(markdown)) {
    for (const auto& n : f.numbers) {
      if (!report_holds(report, n)) {
        missing.push_back(std::move(f));
        break;
      }
    }
  }
  return missing;
}

}  // namespace stereoball::bench_report
