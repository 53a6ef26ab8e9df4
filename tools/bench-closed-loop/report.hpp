#pragma once
// Aggregation of judged runs per scenario and over all runs, the printed table and the JSON.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "acceptance.hpp"

namespace stereoball::bench_closed_loop {

/// One judged run.
struct JudgedRun {
  std::string scenario;
  std::uint64_t seed = 0;
  std::size_t frames = 0;
  RunAcceptance result;
};

/// Figures of a group of runs (one scenario, or all).
struct Summary {
  std::string name;
  int runs = 0;
  int ball_runs = 0;            ///< runs whose scenario has a ball
  KeepFigures keep;             ///< summed over the runs
  double worst_kept = -1.0;     ///< lowest kept / reachable of a run with reachable time (-1: none)
  double detection_rate = 0.0;  ///< found on the ball / visible frames (demo metrics), pooled
  double accept_rate = 0.0;     ///< accepted / visible frames, pooled
  int leave_runs = 0;           ///< runs with at least one judged leave event
  int right_way_runs = 0;       ///< ... whose judged events all turned the right way
  int reacquired_runs = 0;      ///< ... whose judged events were all reacquired in time
  int leave_ok_runs = 0;        ///< ... passing (b): both
  int leave_events = 0, cut_off_events = 0;
  /// Cut-off events are not judged, but the way their search turned is known: how many searched,
  /// and how many of those turned toward the side the ball left on.
  int cut_off_searched = 0, cut_off_right_way = 0;
  std::vector<double> reacquire_s;  ///< reacquisition times of the judged events
  int no_ball_runs = 0, no_ball_ok_runs = 0;
  double longest_following_no_ball_s = 0.0;  ///< max over the no-ball runs
};

/// Sums the runs in runs (all of them; callers group by scenario).
Summary summarize(const std::string& name, const std::vector<const JudgedRun*>& runs,
                  const AcceptanceParams& params);

/// Prints the definitions, the table (one row per scenario, then TOTAL) and the verdicts.
void print_report(std::FILE* out, const std::vector<Summary>& scenarios, const Summary& total,
                  const AcceptanceParams& params);
/// Prints the table alone: one row per summary, then total; first_column heads the names.
void print_table(std::FILE* out, const std::vector<Summary>& rows, const Summary& total,
                 const char* first_column);
/// Prints where the reachable time is lost and every leave event.
void print_details(std::FILE* out, const std::vector<Summary>& scenarios,
                   const std::vector<JudgedRun>& runs);

/// Everything as JSON: params/definitions, every run, per-scenario summaries, the total.
nlohmann::json to_json(const std::vector<JudgedRun>& runs, const std::vector<Summary>& scenarios,
                       const Summary& total, const AcceptanceParams& params);

/// Writes one run frame by frame as CSV (time, truth, track, command) for diagnosis.
void write_trace(std::FILE* out, const std::vector<Sample>& samples);

/// The definitions of the three criteria in words, with the thresholds in force.
std::vector<std::string> definitions(const AcceptanceParams& params);

}  // namespace stereoball::bench_closed_loop
