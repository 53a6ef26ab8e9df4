#include "report.hpp"

#include <algorithm>
#include <cmath>

#include "loop_config.hpp"

namespace stereoball::bench_closed_loop {
namespace {

constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

void add(KeepFigures& to, const KeepFigures& k) {
  to.visible_s += k.visible_s;
  to.fast_s += k.fast_s;
  to.reachable_s += k.reachable_s;
  to.kept_s += k.kept_s;
  to.distance_ok_s += k.distance_ok_s;
  to.bearing_ok_s += k.bearing_ok_s;
  to.following_s += k.following_s;
  to.distance_error_sum_m += k.distance_error_sum_m;
  to.abs_bearing_sum_rad += k.abs_bearing_sum_rad;
  to.reachable_frames += k.reachable_frames;
}

// part / whole in percent with the given printf width, or "-" when whole is zero.
std::string pct(double part, double whole, int width = 5) {
  char buf[32];
  if (whole <= 0.0) {
    std::snprintf(buf, sizeof buf, "%*s", width, "-");
  } else {
    std::snprintf(buf, sizeof buf, "%*.1f", width, 100.0 * part / whole);
  }
  return buf;
}

std::string num(double value, const char* format, bool present = true, int width = 5) {
  char buf[32];
  if (present) {
    std::snprintf(buf, sizeof buf, format, value);
  } else {
    std::snprintf(buf, sizeof buf, "%*s", width, "-");
  }
  return buf;
}

void add_leaves(Summary& s, const std::vector<LeaveEvent>& leaves) {
  const std::size_t judged = judged_leaves(leaves);
  s.leave_events += static_cast<int>(judged);
  s.cut_off_events += static_cast<int>(leaves.size() - judged);
  for (const auto& e : leaves) {
    if (!e.cut_off || e.turned == Side::kNone) continue;
    ++s.cut_off_searched;
    s.cut_off_right_way += e.turned == e.side ? 1 : 0;
  }
  if (judged == 0) return;
  ++s.leave_runs;
  bool right = true, reacquired = true;
  for (const auto& e : leaves) {
    if (e.cut_off) continue;
    right = right && e.right_way;
    reacquired = reacquired && e.reacquired;
    if (e.reacquired) s.reacquire_s.push_back(e.reacquire_s);
  }
  s.right_way_runs += right ? 1 : 0;
  s.reacquired_runs += reacquired ? 1 : 0;
  s.leave_ok_runs += leave_run_ok(leaves) ? 1 : 0;
}

void print_row(std::FILE* out, const Summary& s) {
  const KeepFigures& k = s.keep;
  const bool has_ball = s.ball_runs > 0;
  std::fprintf(
      out, "%-24s %4d %s %s | %7s %s %s %s %s %s | %4d %5s %5s %s %5s | %5s %5s\n", s.name.c_str(),
      s.runs, pct(s.detection_rate, has_ball ? 1 : 0).c_str(),
      pct(s.accept_rate, has_ball ? 1 : 0).c_str(),
      num(k.reachable_s, "%7.1f", has_ball, 7).c_str(), pct(k.kept_s, k.reachable_s).c_str(),
      pct(k.distance_ok_s, k.reachable_s).c_str(), pct(k.bearing_ok_s, k.reachable_s).c_str(),
      pct(k.following_s, k.reachable_s).c_str(),
      pct(s.worst_kept, s.worst_kept >= 0 ? 1 : 0).c_str(), s.leave_runs,
      s.leave_runs ? std::to_string(s.right_way_runs).c_str() : "-",
      s.leave_runs ? std::to_string(s.reacquired_runs).c_str() : "-",
      pct(s.leave_ok_runs, s.leave_runs).c_str(),
      num(sim_loop::percentile(s.reacquire_s, 0.5), "%5.2f", !s.reacquire_s.empty()).c_str(),
      num(s.longest_following_no_ball_s, "%5.2f", s.no_ball_runs > 0).c_str(),
      s.no_ball_runs
          ? (std::to_string(s.no_ball_ok_runs) + "/" + std::to_string(s.no_ball_runs)).c_str()
          : "-");
}

const char* verdict(bool met) {
  return met ? "MET" : "NOT MET";
}

// "N event(s) cut off by the run's end; of those, S searched: R toward the side the ball left
// on" (the second part only when there were some).
std::string cut_off_note(const Summary& t) {
  std::string note = std::to_string(t.cut_off_events) + " event(s) cut off by the run's end";
  if (t.cut_off_events == 0) return note;
  return note + "; of those, " + std::to_string(t.cut_off_searched) +
         " searched: " + std::to_string(t.cut_off_right_way) + " toward the side the ball left on";
}

void print_verdicts(std::FILE* out, const Summary& t, const AcceptanceParams& p) {
  const KeepFigures& k = t.keep;
  if (k.reachable_s > 0) {
    const double kept = k.kept_s / k.reachable_s;
    std::fprintf(out,
                 "(a) ball kept within tolerance %.1f%% of %.1f s reachable (target >= 90%%): %s\n",
                 100.0 * kept, k.reachable_s, verdict(kept >= 0.9));
  } else {
    std::fprintf(out, "(a) not measured: no reachable time in these runs\n");
  }
  if (t.leave_runs > 0) {
    const double ok = static_cast<double>(t.leave_ok_runs) / t.leave_runs;
    std::fprintf(out,
                 "(b) %d of %d runs with a judged leave event turned the right way and reacquired "
                 "within %.0f s = %.1f%% (target >= 95%%): %s  [right way %d/%d, reacquired %d/%d, "
                 "%s]\n",
                 t.leave_ok_runs, t.leave_runs, p.reacquire_limit_s, 100.0 * ok,
                 verdict(ok >= 0.95), t.right_way_runs, t.leave_runs, t.reacquired_runs,
                 t.leave_runs, cut_off_note(t).c_str());
  } else {
    std::fprintf(
        out, "(b) not measured: the ball did not leave the view (for >= %.1f s) in any run%s%s\n",
        p.min_gap_s, t.cut_off_events ? " long enough before the end to judge it" : "",
        t.cut_off_events ? (" [" + cut_off_note(t) + "]").c_str() : "");
  }
  if (t.no_ball_runs > 0) {
    std::fprintf(
        out,
        "(c) %d of %d no-ball runs never in 'following' for more than %.1f s (longest %.2f "
        "s; target: every run): %s\n",
        t.no_ball_ok_runs, t.no_ball_runs, p.max_following_no_ball_s, t.longest_following_no_ball_s,
        verdict(t.no_ball_ok_runs == t.no_ball_runs));
  } else {
    std::fprintf(out, "(c) not measured: no scenario without a ball was run\n");
  }
}

nlohmann::json keep_json(const KeepFigures& k) {
  const double n = k.reachable_frames ? static_cast<double>(k.reachable_frames) : 1.0;
  auto fraction = [&](double part) -> nlohmann::json {
    if (k.reachable_s <= 0) return nullptr;
    return part / k.reachable_s;
  };
  return {{"visible_s", k.visible_s},
          {"too_fast_s", k.fast_s},
          {"reachable_s", k.reachable_s},
          {"kept_s", k.kept_s},
          {"kept_fraction", fraction(k.kept_s)},
          {"distance_ok_fraction", fraction(k.distance_ok_s)},
          {"bearing_ok_fraction", fraction(k.bearing_ok_s)},
          {"following_fraction", fraction(k.following_s)},
          {"mean_distance_error_m", k.distance_error_sum_m / n},
          {"mean_abs_bearing_deg", k.abs_bearing_sum_rad / n * kRadToDeg}};
}

nlohmann::json summary_json(const Summary& s) {
  auto fraction = [](int part, int whole) -> nlohmann::json {
    if (whole == 0) return nullptr;
    return static_cast<double>(part) / whole;
  };
  return {{"name", s.name},
          {"runs", s.runs},
          {"detection_rate", s.ball_runs ? nlohmann::json(s.detection_rate) : nlohmann::json()},
          {"accept_rate_visible", s.ball_runs ? nlohmann::json(s.accept_rate) : nlohmann::json()},
          {"a", keep_json(s.keep)},
          {"a_worst_run_kept_fraction", s.worst_kept >= 0 ? nlohmann::json(s.worst_kept) : nullptr},
          {"b",
           {{"runs_with_leave", s.leave_runs},
            {"right_way_runs", s.right_way_runs},
            {"reacquired_runs", s.reacquired_runs},
            {"ok_runs", s.leave_ok_runs},
            {"ok_fraction", fraction(s.leave_ok_runs, s.leave_runs)},
            {"judged_events", s.leave_events},
            {"cut_off_events", s.cut_off_events},
            {"cut_off_searched", s.cut_off_searched},
            {"cut_off_right_way", s.cut_off_right_way},
            {"reacquire_median_s",
             s.reacquire_s.empty() ? nlohmann::json()
                                   : nlohmann::json(sim_loop::percentile(s.reacquire_s, 0.5))}}},
          {"c",
           {{"no_ball_runs", s.no_ball_runs},
            {"ok_runs", s.no_ball_ok_runs},
            {"longest_following_s", s.longest_following_no_ball_s}}}};
}

}  // namespace

std::vector<std::string> definitions(const AcceptanceParams& p) {
  char a[640], b[900], c[400];
  std::snprintf(a, sizeof a,
                "(a) reachable = ball visible in both eyes and slower than %.2f m/s (the "
                "controller's max_linear_mps), both without a break for at least %.1f s; kept = "
                "|distance - %.2f m| <= %.2f m and |bearing| <= %.1f deg, from the robot's centre "
                "to the ball's centre on the floor (ground truth). Figure: kept / reachable time "
                "over all runs (target >= 90%%).",
                p.max_ball_speed_mps, p.settle_s, p.target_distance_m, p.distance_tolerance_m,
                p.bearing_tolerance_rad * kRadToDeg);
  std::snprintf(b, sizeof b,
                "(b) the ball leaves the view = visible, then out of view of an eye for at least "
                "%.1f s; its side = sign of its bearing at the last visible frame; right way = the "
                "first searching command turning at >= %.2f rad/s turns toward that side (or the "
                "ball is reacquired before any search); reacquired = track following with an "
                "accepted position within %.2f m of the true ball, within %.1f s of leaving. A run "
                "passes if all its judged events do; an event the run's end cuts off before the "
                "limit is not judged. Figure: passing / runs with a judged event (target >= 95%%).",
                p.min_gap_s, p.search_turn_radps, p.on_ball_m, p.reacquire_limit_s);
  std::snprintf(c, sizeof c,
                "(c) scenarios without a ball: longest continuous stretch of track state "
                "'following' (first to last frame). A run passes if it is <= %.1f s (target: "
                "every run).",
                p.max_following_no_ball_s);
  return {a, b, c};
}

Summary summarize(const std::string& name, const std::vector<const JudgedRun*>& runs,
                  const AcceptanceParams& params) {
  Summary s;
  s.name = name;
  double visible = 0, found = 0, accepted = 0;
  for (const JudgedRun* r : runs) {
    const RunAcceptance& a = r->result;
    ++s.runs;
    add(s.keep, a.keep);
    if (a.keep.reachable_s > 0) {
      const double kept = a.keep.kept_s / a.keep.reachable_s;
      s.worst_kept = s.worst_kept < 0 ? kept : std::min(s.worst_kept, kept);
    }
    const auto v = static_cast<double>(a.metrics.visible_frames);
    visible += v;
    found += a.metrics.detection_rate * v;
    accepted += a.metrics.accept_rate_visible * v;
    add_leaves(s, a.leaves);
    if (a.ball_present) {
      ++s.ball_runs;
    } else {
      ++s.no_ball_runs;
      s.no_ball_ok_runs += a.longest_following_no_ball_s <= params.max_following_no_ball_s ? 1 : 0;
      s.longest_following_no_ball_s =
          std::max(s.longest_following_no_ball_s, a.longest_following_no_ball_s);
    }
  }
  s.detection_rate = visible > 0 ? found / visible : 0.0;
  s.accept_rate = visible > 0 ? accepted / visible : 0.0;
  return s;
}

void print_table(std::FILE* out, const std::vector<Summary>& rows, const Summary& total,
                 const char* first_column) {
  std::fprintf(out, "\n%-24s %4s %-11s | %-37s | %-28s | %s\n", "", "", "  detector",
               "(a) kept in tolerance while reachable", "(b) ball leaves the view", "(c) no ball");
  std::fprintf(out, "%-24s %4s %5s %5s | %7s %5s %5s %5s %5s %5s | %4s %5s %5s %5s %5s | %5s %5s\n",
               first_column, "runs", "det%", "acc%", "reach s", "kept%", "dist%", "bear%", "foll%",
               "worst", "runs", "right", "reacq", "pass%", "med s", "max s", "pass");
  for (const auto& s : rows) print_row(out, s);
  print_row(out, total);
}

void print_report(std::FILE* out, const std::vector<Summary>& scenarios, const Summary& total,
                  const AcceptanceParams& params) {
  std::fprintf(out, "\nDefinitions\n");
  for (const auto& d : definitions(params)) std::fprintf(out, "  %s\n", d.c_str());
  print_table(out, scenarios, total, "scenario");
  std::fprintf(out, "\n");
  print_verdicts(out, total, params);
}

void print_details(std::FILE* out, const std::vector<Summary>& scenarios,
                   const std::vector<JudgedRun>& runs) {
  std::fprintf(out, "\nWhere (a) loses time (summed over runs)\n");
  std::fprintf(out, "%-24s %9s %10s %8s %14s %15s %14s\n", "scenario", "visible s", "too fast s",
               "reach s", "mean dist err", "mean |bearing|", "not following");
  for (const auto& s : scenarios) {
    const KeepFigures& k = s.keep;
    if (s.ball_runs == 0) continue;
    const double n = k.reachable_frames ? static_cast<double>(k.reachable_frames) : 1.0;
    std::fprintf(out, "%-24s %9.1f %10.1f %8.1f %12s m %11s deg %12s %%\n", s.name.c_str(),
                 k.visible_s, k.fast_s, k.reachable_s,
                 num(k.distance_error_sum_m / n, "%+.3f", k.reachable_frames > 0).c_str(),
                 num(k.abs_bearing_sum_rad / n * kRadToDeg, "%.2f", k.reachable_frames > 0).c_str(),
                 pct(k.reachable_s - k.following_s, k.reachable_s).c_str());
  }
  std::fprintf(out, "\nLeave events (b)\n");
  std::fprintf(out, "%-24s %5s %7s %6s %8s %13s %s\n", "scenario", "seed", "t s", "side",
               "searched", "reacquired s", "verdict");
  bool any = false;
  for (const auto& r : runs) {
    for (const auto& e : r.result.leaves) {
      any = true;
      const char* v = e.cut_off                       ? "not judged (run ended)"
                      : (e.right_way && e.reacquired) ? "pass"
                      : !e.right_way                  ? "FAIL: wrong way"
                                                      : "FAIL: not reacquired";
      std::fprintf(out, "%-24s %5llu %7.2f %6s %8s %13s %s\n", r.scenario.c_str(),
                   static_cast<unsigned long long>(r.seed), e.t_s, to_string(e.side),
                   to_string(e.turned), num(e.reacquire_s, "%.2f", e.reacquired, 1).c_str(), v);
    }
  }
  if (!any) std::fprintf(out, "(none)\n");
}

void write_trace(std::FILE* out, const std::vector<Sample>& samples) {
  std::fprintf(out,
               "t_s,ball_present,visible,ball_speed_mps,distance_m,bearing_deg,detected,"
               "track_state,accepted,track_x_m,track_z_m,searching,angular_radps,linear_mps\n");
  for (const Sample& s : samples) {
    std::fprintf(out, "%.4f,%d,%d,%.3f,%.4f,%.3f,%d,%d,%d,%.4f,%.4f,%d,%.4f,%.4f\n", s.truth.t_s,
                 s.truth.ball_present, s.truth.visible, s.ball_speed_mps,
                 demo::robot_ball_distance_m(s.truth),
                 demo::robot_ball_bearing_rad(s.truth) * kRadToDeg, s.detection.found,
                 static_cast<int>(s.track.state), s.track.accepted, s.track.position_m[0],
                 s.track.position_m[2], s.searching, s.angular_radps, s.linear_mps);
  }
}

nlohmann::json to_json(const std::vector<JudgedRun>& runs, const std::vector<Summary>& scenarios,
                       const Summary& total, const AcceptanceParams& p) {
  nlohmann::json j;
  j["definitions"] = definitions(p);
  j["params"] = {{"target_distance_m", p.target_distance_m},
                 {"distance_tolerance_m", p.distance_tolerance_m},
                 {"bearing_tolerance_deg", p.bearing_tolerance_rad * kRadToDeg},
                 {"max_ball_speed_mps", p.max_ball_speed_mps},
                 {"settle_s", p.settle_s},
                 {"min_gap_s", p.min_gap_s},
                 {"reacquire_limit_s", p.reacquire_limit_s},
                 {"search_turn_radps", p.search_turn_radps},
                 {"on_ball_m", p.on_ball_m},
                 {"max_following_no_ball_s", p.max_following_no_ball_s}};
  for (const auto& r : runs) {
    nlohmann::json leaves = nlohmann::json::array();
    for (const auto& e : r.result.leaves) {
      leaves.push_back({{"t_s", e.t_s},
                        {"side", to_string(e.side)},
                        {"searched", to_string(e.turned)},
                        {"right_way", e.right_way},
                        {"reacquired", e.reacquired},
                        {"reacquire_s", e.reacquired ? nlohmann::json(e.reacquire_s) : nullptr},
                        {"judged", !e.cut_off}});
    }
    j["runs"].push_back({{"scenario", r.scenario},
                         {"seed", r.seed},
                         {"frames", r.frames},
                         {"ball_present", r.result.ball_present},
                         {"detection_rate", r.result.metrics.detection_rate},
                         {"a", keep_json(r.result.keep)},
                         {"b", leaves},
                         {"c_longest_following_s", r.result.longest_following_no_ball_s}});
  }
  for (const auto& s : scenarios) j["scenarios"].push_back(summary_json(s));
  j["total"] = summary_json(total);
  return j;
}

}  // namespace stereoball::bench_closed_loop
