#include "real_stereo_report.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <sstream>

#include "common/util/enum_names.hpp"
#include "common/util/json_text.hpp"

namespace stereoball::real_stereo {
namespace {

std::string fmt(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return buf;
}

std::string percent(int n, int of) {
  return of > 0 ? fmt("%5.1f %%", 100.0 * n / of) : std::string("    - ");
}

std::string counts_line(const std::string& label, const Counts& c) {
  return fmt("  %-20s %3d %s  %3d %s  %3d %s  %3d\n", label.c_str(), c.correct,
             percent(c.correct, c.total()).c_str(), c.wrong, percent(c.wrong, c.total()).c_str(),
             c.missed, percent(c.missed, c.total()).c_str(), c.total());
}

// The bands' keys in the JSON (string literals: data() ends in a NUL).
constexpr util::EnumName<Band> kBandJsonKeys[] = {
    {Band::kWithin2, "dy_le_2"}, {Band::k2To10, "dy_2_to_10"}, {Band::kOver10, "dy_over_10"}};

const char* band_key(Band b) {
  return util::name_of(kBandJsonKeys, b, "?").data();
}

// A number, or null when it is not finite (JSON has no NaN).
std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt("%.6g", v);
}

std::string json_counts(const Counts& c) {
  return fmt("{\"correct\": %d, \"wrong\": %d, \"missed\": %d, \"pairs\": %d, ", c.correct, c.wrong,
             c.missed, c.total()) +
         "\"correct_fraction\": " +
         (c.total() ? json_number(double(c.correct) / c.total()) : std::string("null")) + "}";
}

// Another method on the left eye alone beside the pipeline (RunOptions::reference).
std::string reference_text(const std::string& method, const std::vector<PairScore>& scores,
                           const RunResult& run, const Summary& s) {
  const ReferenceSummary r = summarize_reference(scores, run.reference);
  return fmt(
      "reference, %s on the rectified left eye alone (no stereo), same frames (%zu): CPU "
      "median %.1f ms; with the frame's decode (%.1f ms) %.1f ms per frame, against the "
      "pipeline's %.1f ms (median of the per-frame ratios pipeline / reference %.2f); the "
      "ball's centre among its circles in %d of %d scored pairs\n",
      method.c_str(), r.frames, r.median_detect_ms, r.median_decode_ms, r.median_frame_ms,
      s.median_cpu_ms, r.median_pipeline_ratio, r.ball_among_circles, r.scored);
}

std::string reference_json(const ReportContext& ctx, const std::vector<PairScore>& scores,
                           const RunResult& run) {
  const ReferenceSummary r = summarize_reference(scores, run.reference);
  return "  \"reference\": {\"method\": " + util::json_quoted(ctx.options.reference) +
         ", \"frames\": " + std::to_string(r.frames) +
         ", \"median_detect_cpu_ms\": " + json_number(r.median_detect_ms) +
         ", \"median_decode_cpu_ms\": " + json_number(r.median_decode_ms) +
         ", \"median_frame_cpu_ms\": " + json_number(r.median_frame_ms) +
         ", \"median_pipeline_over_reference\": " + json_number(r.median_pipeline_ratio) +
         ", \"scored_pairs\": " + std::to_string(r.scored) +
         ", \"ball_among_circles\": " + std::to_string(r.ball_among_circles) + "},\n";
}

std::string mode_label(const RunResult& run, const RunOptions& o) {
  if (run.mode == "in-process")
    return "IN-PROCESS (the detector's pipeline library in this process, same frames and "
           "conversions; NOT the DDS path: acceptance figures come from the default DDS mode)";
  return "DDS (camera_server + ball_detector processes, domain " + std::to_string(o.domain) + ")";
}

}  // namespace

std::vector<PairScore> score_run(const RealStereoSet& set, const RunResult& run,
                                 const ScoreRules& rules) {
  std::vector<PairScore> out;
  for (std::size_t i = 0; i < set.truth.size() && i < run.pairs.size(); ++i) {
    if (!run.pairs[i].detection) continue;
    out.push_back(score_pair(scaled(set.truth[i], run.scale), *run.pairs[i].detection, rules));
  }
  return out;
}

std::string format_table(const ReportContext& ctx, const RunResult& run,
                         const std::vector<PairScore>& scores, const Summary& s, bool verbose) {
  const RealStereoSet& set = *ctx.set;
  const RunOptions& o = ctx.options;
  std::ostringstream t;
  t << "stereoball bench real-stereo: " << mode_label(run, o) << "\n";
  t << "set:         " << set.dir << " (" << set.truth.size() << " pairs, " << set.image_size.width
    << "x" << set.image_size.height << ")\n";
  t << "truth:       " << set.truth_path << "\n";
  t << "calibration: " << set.calibration_path << "\n";
  t << "played:      " << run.played_size.width << "x" << run.played_size.height << " ("
    << (o.width_px ? "publish_width_px " + std::to_string(o.width_px) + ", truth scaled by " +
                         fmt("%.4f", run.scale)
                   : std::string("native"))
    << "), frame_encoding " << o.frame_encoding
    << (o.frame_encoding == "jpeg"
            ? " quality " + std::to_string(o.jpeg_quality) + " chroma " + o.jpeg_chroma
            : "");
  if (run.mode == "dds") t << ", " << fmt("%.2f", o.rate_hz) << " Hz";
  t << "\n";
  t << "detector:    " << ctx.detector_base;
  if (ctx.config->changes.empty()) t << " (as shipped)";
  for (const auto& c : ctx.config->changes) t << "\n             + " << c;
  t << "\n";
  for (const auto& n : run.notes) t << "note:        " << n << "\n";
  const int scored_total = s.overall.total();
  t << "\nscored: " << scored_total << " pairs with a radius in the truth";
  if (!s.excluded.empty()) {
    t << "; excluded " << s.excluded.size() << " (";
    for (std::size_t i = 0; i < s.excluded.size(); ++i) t << (i ? ", " : "") << s.excluded[i];
    t << ")";
  }
  t << "\n";
  t << fmt("  %-20s %11s  %11s  %11s  %5s\n", "", "correct", "wrong", "missed", "pairs");
  t << counts_line("all", s.overall);
  for (const auto& [band, c] : s.bands) t << counts_line(band_name(band), c);
  t << "correct: left centre within max(6 px, 0.35 r) of the truth and, where the truth's depth "
       "is consistent, depth within 5 % of Z_m\n";
  t << "\nmisses by reason (numbers as #):\n";
  if (s.miss_reasons.empty()) t << "  none\n";
  for (const auto& [why, n] : s.miss_reasons) t << fmt("  %3d  %s\n", n, why.c_str());
  t << "\nwrong pairs:\n";
  bool any_wrong = false;
  for (const auto& p : scores) {
    if (p.verdict != Verdict::kWrong) continue;
    any_wrong = true;
    t << "  pair " << p.truth.pair << ": " << p.why << "\n";
  }
  if (!any_wrong) t << "  none\n";
  t << fmt(
      "\ndetector time per stereo frame (processing_ms, %zu frames): median %.1f ms, p90 "
      "%.1f ms\n",
      s.timed_frames, s.median_ms, s.p90_ms);
  if (s.cpu_frames > 0)
    t << fmt(
        "detector CPU time per stereo frame (this thread, %zu frames): median %.1f ms, p90 "
        "%.1f ms (less disturbed by a busy machine than the wall time above)\n",
        s.cpu_frames, s.median_cpu_ms, s.p90_cpu_ms);
  if (!run.cpu_by_search.empty()) {
    t << fmt(
        "detector CPU time by search (ms per stereo frame over the %zu frames; frames that "
        "ran it, and its mean there):\n",
        s.cpu_frames);
    for (const SearchCpu& e : run.cpu_by_search)
      t << fmt("  %-18s %7.2f ms  (%3d frames, %7.2f ms each)\n", e.path.c_str(),
               s.cpu_frames ? e.total_ms / double(s.cpu_frames) : 0.0, e.frames,
               e.frames ? e.total_ms / e.frames : 0.0);
  }
  if (!run.reference.empty()) t << reference_text(o.reference, scores, run, s);
  if (verbose) {
    t << "\npairs:\n";
    for (const auto& p : scores) {
      const Detection& d = p.detection;
      std::string line =
          fmt("  %-5s %-20s |dy| %5.1f  %-8s", p.truth.pair.c_str(), p.truth.left.c_str(),
              std::abs(p.truth.dy_px), verdict_name(p.verdict));
      if (p.verdict == Verdict::kExcluded) {
        line += std::string(" ") + exclusion_name(p.exclusion) + "; detector: " + d.status;
      } else if (d.found) {
        line +=
            fmt(" centre %.1f px off (r %.0f), z %.2f m", p.centre_error_px, p.truth.left_r, d.z_m);
        if (std::isfinite(p.truth.z_m))
          line += fmt(" vs %.2f m (%+.1f %%%s)", p.truth.z_m, 100.0 * p.depth_error,
                      p.truth.depth_checked() ? "" : ", not checked");
      } else {
        line += " " + d.status + ": " + d.reason;
      }
      t << line << fmt("  %.1f ms\n", d.processing_ms);
    }
  }
  t << "\nrun errors: ";
  if (run.errors.empty()) {
    t << "none (every pair got exactly one detection)\n";
  } else {
    t << run.errors.size() << " -- THE FIGURES ABOVE ARE INCOMPLETE\n";
    for (const auto& e : run.errors) t << "  " << e << "\n";
  }
  return t.str();
}

std::string format_json(const ReportContext& ctx, const RunResult& run,
                        const std::vector<PairScore>& scores, const Summary& s) {
  const RealStereoSet& set = *ctx.set;
  const RunOptions& o = ctx.options;
  std::ostringstream j;
  j << "{\n";
  j << "  \"mode\": " << util::json_quoted(run.mode) << ",\n";
  j << "  \"set\": " << util::json_quoted(set.dir) << ",\n";
  j << "  \"truth\": " << util::json_quoted(set.truth_path) << ",\n";
  j << "  \"calibration\": " << util::json_quoted(set.calibration_path) << ",\n";
  j << "  \"image_size\": [" << set.image_size.width << ", " << set.image_size.height << "],\n";
  j << "  \"played_size\": [" << run.played_size.width << ", " << run.played_size.height << "],\n";
  j << "  \"truth_scale\": " << json_number(run.scale) << ",\n";
  j << "  \"frame_encoding\": " << util::json_quoted(o.frame_encoding) << ",\n";
  j << "  \"jpeg_quality\": " << o.jpeg_quality << ",\n";
  j << "  \"jpeg_chroma\": " << util::json_quoted(o.jpeg_chroma) << ",\n";
  j << "  \"rate_hz\": " << json_number(run.mode == "dds" ? o.rate_hz : NAN) << ",\n";
  j << "  \"domain\": " << (run.mode == "dds" ? std::to_string(o.domain) : "null") << ",\n";
  j << "  \"detector_config\": {\"base\": " << util::json_quoted(ctx.detector_base)
    << ", \"changes\": [";
  for (std::size_t i = 0; i < ctx.config->changes.size(); ++i)
    j << (i ? ", " : "") << util::json_quoted(ctx.config->changes[i]);
  j << "], \"yaml\": " << util::json_quoted(ctx.config->yaml) << "},\n";
  j << "  \"pairs_in_set\": " << set.truth.size() << ",\n";
  j << "  \"overall\": " << json_counts(s.overall) << ",\n";
  j << "  \"bands\": {";
  bool first = true;
  for (const auto& [band, c] : s.bands) {
    j << (first ? "" : ", ") << util::json_quoted(band_key(band)) << ": " << json_counts(c);
    first = false;
  }
  j << "},\n";
  j << "  \"excluded\": [";
  for (std::size_t i = 0; i < s.excluded.size(); ++i)
    j << (i ? ", " : "") << util::json_quoted(s.excluded[i]);
  j << "],\n";
  j << "  \"miss_reasons\": {";
  first = true;
  for (const auto& [why, n] : s.miss_reasons) {
    j << (first ? "" : ", ") << util::json_quoted(why) << ": " << n;
    first = false;
  }
  j << "},\n";
  j << "  \"ms_per_frame\": {\"median\": " << json_number(s.median_ms)
    << ", \"p90\": " << json_number(s.p90_ms) << ", \"frames\": " << s.timed_frames << "},\n";
  j << "  \"cpu_ms_per_frame\": ";
  if (s.cpu_frames > 0) {
    j << "{\"median\": " << json_number(s.median_cpu_ms)
      << ", \"p90\": " << json_number(s.p90_cpu_ms) << ", \"frames\": " << s.cpu_frames << "},\n";
  } else {
    j << "null,\n";
  }
  j << "  \"cpu_ms_by_search\": {";
  for (std::size_t i = 0; i < run.cpu_by_search.size(); ++i) {
    const SearchCpu& e = run.cpu_by_search[i];
    j << (i ? ", " : "") << util::json_quoted(e.path)
      << ": {\"total_ms\": " << json_number(e.total_ms) << ", \"frames\": " << e.frames << "}";
  }
  j << "},\n";
  if (!run.reference.empty()) j << reference_json(ctx, scores, run);
  j << "  \"run_errors\": [";
  for (std::size_t i = 0; i < run.errors.size(); ++i)
    j << (i ? ", " : "") << util::json_quoted(run.errors[i]);
  j << "],\n";
  j << "  \"notes\": [";
  for (std::size_t i = 0; i < run.notes.size(); ++i)
    j << (i ? ", " : "") << util::json_quoted(run.notes[i]);
  j << "],\n";
  j << "  \"pairs\": [";
  for (std::size_t i = 0; i < scores.size(); ++i) {
    const PairScore& p = scores[i];
    const Detection& d = p.detection;
    j << (i ? "," : "") << "\n    {\"pair\": " << util::json_quoted(p.truth.pair)
      << ", \"left\": " << util::json_quoted(p.truth.left)
      << ", \"verdict\": " << util::json_quoted(verdict_name(p.verdict))
      << ", \"excluded_because\": "
      << (p.verdict == Verdict::kExcluded ? util::json_quoted(exclusion_name(p.exclusion)) : "null")
      << ", \"band\": " << util::json_quoted(band_key(p.band))
      << ", \"dy_px\": " << json_number(p.truth.dy_px)
      << ", \"status\": " << util::json_quoted(d.status)
      << ", \"reason\": " << util::json_quoted(d.reason)
      << ", \"left_x_px\": " << json_number(d.left_x_px)
      << ", \"left_y_px\": " << json_number(d.left_y_px)
      << ", \"left_r_px\": " << json_number(d.left_r_px) << ", \"z_m\": " << json_number(d.z_m)
      << ", \"truth_left_x_px\": " << json_number(p.truth.left_cx)
      << ", \"truth_left_y_px\": " << json_number(p.truth.left_cy)
      << ", \"truth_left_r_px\": " << json_number(p.truth.left_r)
      << ", \"truth_z_m\": " << json_number(p.truth.z_m)
      << ", \"depth_checked\": " << (p.truth.depth_checked() ? "true" : "false")
      << ", \"centre_error_px\": " << json_number(d.found ? p.centre_error_px : NAN)
      << ", \"depth_error\": "
      << json_number(d.found && std::isfinite(p.truth.z_m) ? p.depth_error : NAN)
      << ", \"why_wrong\": " << (p.why.empty() ? "null" : util::json_quoted(p.why))
      << ", \"processing_ms\": " << json_number(d.processing_ms) << "}";
  }
  j << "\n  ]\n}\n";
  return j.str();
}

}  // namespace stereoball::real_stereo
