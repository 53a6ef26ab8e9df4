#include "ball_detector/core/circle_labels.hpp"

#include <charconv>
#include <cmath>
#include <optional>

namespace stereoball::ball_detector {
namespace {

std::vector<std::string_view> split_words(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

std::optional<double> parse_number(std::string_view word) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
  if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v))
    return std::nullopt;
  return v;
}

// Applies one non-empty line to labels; returns an error message or "".
std::string apply_line(const std::vector<std::string_view>& w, CircleLabels& labels,
                       bool& have_image, bool& have_split) {
  const std::string_view key = w[0];
  if (key == "image") {
    if (w.size() != 2) return "'image' takes one path";
    if (have_image) return "second 'image' line";
    labels.image_path = std::string(w[1]);
    have_image = true;
    return "";
  }
  if (key == "split") {
    if (w.size() != 2 || (w[1] != "tune" && w[1] != "report"))
      return "'split' takes 'tune' or 'report'";
    if (have_split) return "second 'split' line";
    labels.split = w[1] == "tune" ? LabelSplit::tune : LabelSplit::report;
    have_split = true;
    return "";
  }
  if (key == "circle") {
    if (w.size() != 4) return "'circle' takes three numbers: x_px y_px radius_px";
    const auto x = parse_number(w[1]), y = parse_number(w[2]), r = parse_number(w[3]);
    if (!x || !y || !r) return "'circle' values must be finite numbers";
    if (!(*r > 0.0)) return "circle radius must be > 0";
    labels.circles.push_back({*x, *y, *r, 1.0});
    return "";
  }
  if (key == "min_radius") {
    if (w.size() != 2) return "'min_radius' takes one number: radius_px";
    if (labels.min_radius_px) return "second 'min_radius' line";
    const auto r = parse_number(w[1]);
    if (!r || !(*r > 0.0)) return "'min_radius' must be a finite number > 0";
    labels.min_radius_px = *r;
    return "";
  }
  return "unknown key '" + std::string(key) + "' (expected image, split, circle or min_radius)";
}

}  // namespace

std::variant<CircleLabels, std::string> parse_circle_labels(std::string_view text,
                                                            const std::string& source) {
  CircleLabels labels;
  bool have_image = false, have_split = false;
  int line_number = 0;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t eol = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_number;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    const auto words = split_words(line);
    if (words.empty()) continue;
    if (std::string e = apply_line(words, labels, have_image, have_split); !e.empty())
      return source + ":" + std::to_string(line_number) + ": " + e;
  }
  if (!have_image) return source + ": no 'image' line";
  if (!have_split) return source + ": no 'split' line";
  return labels;
}

const char* split_name(LabelSplit split) {
  return split == LabelSplit::tune ? "tune" : "report";
}

}  // namespace stereoball::ball_detector
