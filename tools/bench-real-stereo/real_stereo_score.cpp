#include "real_stereo_score.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>

#include "common/util/enum_names.hpp"

namespace stereoball::real_stereo {
namespace {

// Largest magnitude a pixel coordinate, radius or depth of a truth file may have: anything
// beyond is a typo (or an overflow), not a ball.
constexpr double kMaxCoordinatePx = 1e6;
constexpr double kMaxRadiusPx = 1e5;
constexpr double kMaxDepthM = 1e4;

const std::vector<std::string>& required_columns() {
  static const std::vector<std::string> kColumns = {
      "pair",         "left",        "right",         "rect_left_cx",
      "rect_left_cy", "rect_left_r", "rect_right_cx", "rect_right_cy",
      "rect_right_r", "dy_mean",     "Z_m",           "flag"};
  return kColumns;
}

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return s.substr(b, e - b);
}

std::vector<std::string> split(const std::string& line, const std::string& separators) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (separators.find(c) != std::string::npos) {
      out.emplace_back();
    } else {
      out.back() += c;
    }
  }
  for (auto& f : out) f = trim(f);
  return out;
}

std::string fmt(const char* format, double a, double b = 0, double c = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, format, a, b, c);
  return buf;
}

// One row's fields by column name, with errors naming file, line and column.
class RowReader {
 public:
  RowReader(const std::string& name, std::size_t line, const std::vector<std::string>& fields,
            const std::map<std::string, std::size_t>& columns)
      : where_(name + ":" + std::to_string(line) + ": "), fields_(fields), columns_(columns) {}

  const std::string& text(const std::string& column) const { return fields_[columns_.at(column)]; }

  // A number; empty or "nan" gives NaN when may_be_nan, else an error.
  std::optional<double> number(const std::string& column, bool may_be_nan, double max_abs) {
    const std::string& t = text(column);
    std::string lower = t;
    for (auto& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (t.empty() || lower == "nan") {
      if (may_be_nan) return std::nan("");
      return fail("column '" + column + "' must be a number, got " +
                  (t.empty() ? std::string("nothing") : "'" + t + "'"));
    }
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size()) {
      return fail("column '" + column + "': '" + t + "' is not a number");
    }
    if (!std::isfinite(v) || std::abs(v) > max_abs) {
      return fail("column '" + column + "': " + t +
                  " is out of range (|value| <= " + fmt("%g", max_abs) + ")");
    }
    return v;
  }

  std::optional<double> fail(const std::string& what) {
    if (!error_) error_ = where_ + what;
    return std::nullopt;
  }
  const std::optional<std::string>& error() const { return error_; }
  const std::string& where() const { return where_; }

 private:
  std::string where_;
  const std::vector<std::string>& fields_;
  const std::map<std::string, std::size_t>& columns_;
  std::optional<std::string> error_;
};

// The row of fields, or the error naming what is wrong with them.
Result<TruthRow> read_row(RowReader& r, std::size_t line) {
  TruthRow row;
  row.line = line;
  row.pair = r.text("pair");
  row.left = r.text("left");
  row.right = r.text("right");
  if (row.pair.empty()) r.fail("column 'pair' is empty");
  for (const auto* file : {&row.left, &row.right}) {
    const std::string column = file == &row.left ? "left" : "right";
    if (file->empty()) r.fail("column '" + column + "' names no image");
    if (file->find('/') != std::string::npos || *file == "." || *file == "..")
      r.fail("column '" + column + "': '" + *file + "' must be a file name in " + column + "/");
  }
  auto take = [&](const std::string& column, double& out, bool may_be_nan, double max_abs) {
    if (auto v = r.number(column, may_be_nan, max_abs)) out = *v;
  };
  take("rect_left_cx", row.left_cx, false, kMaxCoordinatePx);
  take("rect_left_cy", row.left_cy, false, kMaxCoordinatePx);
  take("rect_left_r", row.left_r, true, kMaxRadiusPx);
  take("rect_right_cx", row.right_cx, false, kMaxCoordinatePx);
  take("rect_right_cy", row.right_cy, false, kMaxCoordinatePx);
  take("rect_right_r", row.right_r, true, kMaxRadiusPx);
  take("dy_mean", row.dy_px, false, kMaxCoordinatePx);
  take("Z_m", row.z_m, true, kMaxDepthM);
  for (const double* radius : {&row.left_r, &row.right_r}) {
    if (!std::isnan(*radius) && !(*radius > 0)) {
      r.fail(std::string("column '") + (radius == &row.left_r ? "rect_left_r" : "rect_right_r") +
             "': a radius must be positive (or nan: none)");
    }
  }
  if (!std::isnan(row.z_m) && !(row.z_m > 0))
    r.fail("column 'Z_m': a depth must be positive (or nan: unknown)");
  for (auto& f : split(r.text("flag"), "|;"))
    if (!f.empty()) row.flags.push_back(f);
  if (r.error()) return Error{*r.error()};
  return row;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// Nearest-rank percentile (q in (0, 1]).
double percentile_of(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const auto rank = static_cast<std::size_t>(std::ceil(q * static_cast<double>(v.size())));
  return v[std::clamp<std::size_t>(rank, 1, v.size()) - 1];
}

}  // namespace

bool TruthRow::has_flag(const std::string& flag) const {
  return std::find(flags.begin(), flags.end(), flag) != flags.end();
}

Exclusion TruthRow::exclusion() const {
  if (has_flag("unusable") || has_flag("clicks_not_on_ball_edges")) return Exclusion::kUnusable;
  if (std::isnan(left_r) || has_flag("no_radius")) return Exclusion::kNoRadius;
  return Exclusion::kNone;
}

bool TruthRow::depth_checked() const {
  return std::isfinite(z_m) && !has_flag("diam_inconsistent");
}

Result<std::vector<TruthRow>> parse_truth(const std::string& text, const std::string& name) {
  std::vector<TruthRow> rows;
  std::map<std::string, std::size_t> columns;
  std::size_t header_size = 0;
  std::set<std::string> pairs;
  std::size_t line_no = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string where = name + ":" + std::to_string(line_no) + ": ";
    if (line.find('\0') != std::string::npos) return Error{where + "holds a NUL byte (binary?)"};
    if (line.find('"') != std::string::npos)
      return Error{where + "quoted fields are not supported (the truth has no commas in fields)"};
    if (line_no == 1) {
      const auto names = split(line, ",");
      for (std::size_t i = 0; i < names.size(); ++i) {
        if (!columns.emplace(names[i], i).second)
          return Error{where + "column '" + names[i] + "' appears twice in the header"};
      }
      header_size = names.size();
      for (const auto& c : required_columns()) {
        if (!columns.count(c))
          return Error{where + "the header has no column '" + c +
                       "' (needed: pair,left,right,rect_left_cx,rect_left_cy,rect_left_r,"
                       "rect_right_cx,rect_right_cy,rect_right_r,dy_mean,Z_m,flag)"};
      }
      continue;
    }
    if (trim(line).empty()) continue;
    const auto fields = split(line, ",");
    if (fields.size() != header_size) {
      return Error{where + std::to_string(fields.size()) + " fields but the header names " +
                   std::to_string(header_size) + " columns"};
    }
    RowReader reader(name, line_no, fields, columns);
    auto row = read_row(reader, line_no);
    if (!row) return Error{row.error()};
    if (!pairs.insert(row->pair).second)
      return Error{where + "pair '" + row->pair + "' appears twice"};
    rows.push_back(std::move(*row));
  }
  if (line_no == 0) return Error{name + ":1: empty file (expected a header line)"};
  if (rows.empty()) return Error{name + ": no pairs after the header"};
  return rows;
}

TruthRow scaled(const TruthRow& row, double factor) {
  TruthRow s = row;
  // Pixel centres map as the image is area-scaled (camera_server's publish_width_px and its
  // scaled calibration): x' = (x + 0.5) s - 0.5. dy_px stays in the truth file's pixels: the
  // bands name the same pairs at every width.
  for (double* v : {&s.left_cx, &s.left_cy, &s.right_cx, &s.right_cy})
    *v = (*v + 0.5) * factor - 0.5;
  for (double* v : {&s.left_r, &s.right_r}) *v *= factor;
  return s;
}

// The names tables print (string literals: a name's data() ends in a NUL).
constexpr util::EnumName<Band> kBandNames[] = {{Band::kWithin2, "|dy| <= 2 px"},
                                               {Band::k2To10, "2 < |dy| <= 10 px"},
                                               {Band::kOver10, "|dy| > 10 px"}};
constexpr util::EnumName<Verdict> kVerdictNames[] = {{Verdict::kCorrect, "correct"},
                                                     {Verdict::kWrong, "wrong"},
                                                     {Verdict::kMissed, "missed"},
                                                     {Verdict::kExcluded, "excluded"}};
constexpr util::EnumName<Exclusion> kExclusionNames[] = {
    {Exclusion::kNone, "scored"},
    {Exclusion::kNoRadius, "no radius in the truth"},
    {Exclusion::kUnusable, "truth unusable (flagged)"}};

const char* band_name(Band band) {
  return util::name_of(kBandNames, band, "?").data();
}

Band band_of(double dy_px) {
  const double a = std::abs(dy_px);
  if (a <= 2.0) return Band::kWithin2;
  if (a <= 10.0) return Band::k2To10;
  return Band::kOver10;
}

namespace {

double centre_allowance_px(const TruthRow& truth, const ScoreRules& rules) {
  return std::max(rules.min_centre_px, rules.centre_per_radius * truth.left_r);
}

}  // namespace

bool centre_matches(const TruthRow& truth, double x_px, double y_px, const ScoreRules& rules) {
  const double error = std::hypot(x_px - truth.left_cx, y_px - truth.left_cy);
  return std::isfinite(error) && error <= centre_allowance_px(truth, rules);
}

PairScore score_pair(const TruthRow& truth, const Detection& detection, const ScoreRules& rules) {
  PairScore s;
  s.truth = truth;
  s.band = band_of(truth.dy_px);
  s.detection = detection;
  s.exclusion = truth.exclusion();
  if (s.exclusion != Exclusion::kNone) {
    s.verdict = Verdict::kExcluded;
    return s;
  }
  if (!detection.found) {
    s.verdict = Verdict::kMissed;
    return s;
  }
  s.verdict = Verdict::kWrong;
  s.centre_error_px =
      std::hypot(detection.left_x_px - truth.left_cx, detection.left_y_px - truth.left_cy);
  if (std::isfinite(truth.z_m)) s.depth_error = (detection.z_m - truth.z_m) / truth.z_m;
  if (!centre_matches(truth, detection.left_x_px, detection.left_y_px, rules)) {
    s.why = fmt("left centre %.1f px from the truth (allowed %.1f px)", s.centre_error_px,
                centre_allowance_px(truth, rules));
    return s;
  }
  if (truth.depth_checked() &&
      !(std::isfinite(detection.z_m) && std::abs(s.depth_error) <= rules.depth_fraction)) {
    s.why = fmt("depth %.2f m, truth %.2f m (%+.1f %%)", detection.z_m, truth.z_m,
                100.0 * s.depth_error);
    return s;
  }
  s.verdict = Verdict::kCorrect;
  return s;
}

void Counts::add(Verdict v) {
  if (v == Verdict::kCorrect) ++correct;
  if (v == Verdict::kWrong) ++wrong;
  if (v == Verdict::kMissed) ++missed;
}

std::string reason_kind(const std::string& status, const std::string& reason) {
  std::string out = status + ": ";
  bool in_number = false;
  for (std::size_t i = 0; i < reason.size(); ++i) {
    const char c = reason[i];
    const bool digit = std::isdigit(static_cast<unsigned char>(c)) != 0;
    // A number: digits with '.', and a sign in front of them.
    const bool part = digit || (in_number && c == '.' && i + 1 < reason.size() &&
                                std::isdigit(static_cast<unsigned char>(reason[i + 1])));
    const bool sign = (c == '+' || c == '-') && i + 1 < reason.size() &&
                      std::isdigit(static_cast<unsigned char>(reason[i + 1])) &&
                      (i == 0 || !std::isalnum(static_cast<unsigned char>(reason[i - 1])));
    if (part || sign) {
      if (!in_number) out += '#';
      in_number = true;
    } else {
      in_number = false;
      out += c;
    }
  }
  return out;
}

Summary summarize(const std::vector<PairScore>& pairs) {
  Summary s;
  for (Band b : {Band::kWithin2, Band::k2To10, Band::kOver10}) s.bands[b] = Counts{};
  std::vector<double> ms, cpu;
  for (const auto& p : pairs) {
    if (std::isfinite(p.detection.cpu_ms) && p.detection.cpu_ms >= 0)
      cpu.push_back(p.detection.cpu_ms);
    if (std::isfinite(p.detection.processing_ms) && p.detection.processing_ms >= 0)
      ms.push_back(p.detection.processing_ms);
    if (p.verdict == Verdict::kExcluded) {
      s.excluded.push_back(p.truth.pair + ": " + exclusion_name(p.exclusion));
      continue;
    }
    s.overall.add(p.verdict);
    s.bands[p.band].add(p.verdict);
    if (p.verdict == Verdict::kMissed)
      ++s.miss_reasons[reason_kind(p.detection.status, p.detection.reason)];
  }
  s.timed_frames = ms.size();
  s.median_ms = median_of(ms);
  s.p90_ms = percentile_of(ms, 0.9);
  s.cpu_frames = cpu.size();
  s.median_cpu_ms = median_of(cpu);
  s.p90_cpu_ms = percentile_of(cpu, 0.9);
  return s;
}

ReferenceSummary summarize_reference(const std::vector<PairScore>& pairs,
                                     const std::vector<std::optional<ReferenceFrame>>& frames,
                                     const ScoreRules& rules) {
  ReferenceSummary s;
  std::vector<double> detect, decode, frame, ratio;
  for (std::size_t i = 0; i < pairs.size() && i < frames.size(); ++i) {
    if (!frames[i]) continue;
    const ReferenceFrame& f = *frames[i];
    detect.push_back(f.detect_cpu_ms);
    decode.push_back(f.decode_cpu_ms);
    frame.push_back(f.detect_cpu_ms + f.decode_cpu_ms);
    const double pipeline = pairs[i].detection.cpu_ms;
    if (std::isfinite(pipeline) && frame.back() > 0) ratio.push_back(pipeline / frame.back());
    if (pairs[i].verdict == Verdict::kExcluded) continue;
    ++s.scored;
    const bool hit = std::any_of(f.circles.begin(), f.circles.end(), [&](const ReferenceCircle& c) {
      return centre_matches(pairs[i].truth, c.x_px, c.y_px, rules);
    });
    if (hit) ++s.ball_among_circles;
  }
  s.frames = detect.size();
  s.median_detect_ms = median_of(detect);
  s.median_decode_ms = median_of(decode);
  s.median_frame_ms = median_of(frame);
  s.median_pipeline_ratio = median_of(ratio);
  return s;
}

const char* verdict_name(Verdict v) {
  return util::name_of(kVerdictNames, v, "?").data();
}

const char* exclusion_name(Exclusion e) {
  return util::name_of(kExclusionNames, e, "?").data();
}

}  // namespace stereoball::real_stereo
