#include "scene_report.hpp"

#include <map>

namespace stereoball::bench_tracking {
namespace {

double pct(long part, long whole) {
  return whole ? 100.0 * part / whole : 0.0;
}

void print_header(std::FILE* out, const char* first) {
  std::fprintf(out, "%-22s %6s %9s %9s %9s %9s %12s\n", first, "scenes", "fully vis", "detect %",
               "accept %", "no-ball", "false acc %");
}

void print_row(std::FILE* out, const std::string& name, const SceneFigures& f) {
  std::fprintf(out, "%-22s %6d %9ld %9.2f %9.2f %9ld %12.2f\n", name.c_str(), f.scenes,
               f.fully_visible, pct(f.detected, f.fully_visible), pct(f.accepted, f.fully_visible),
               f.no_ball, pct(f.false_accepted, f.no_ball));
}

// Fully visible frames not accepted on the ball, by where the chain lost them.
void print_miss_causes(std::FILE* out, const std::vector<RunResult>& runs) {
  std::map<std::string, std::map<std::string, long>> by_scene;  // scene -> cause -> frames
  std::map<std::string, long> total;
  for (const RunResult& r : runs)
    for (const FrameRecord& f : r.frames) {
      if (f.miss_cause.empty()) continue;
      ++by_scene[r.scenario][f.miss_cause];
      ++total[f.miss_cause];
    }
  std::fprintf(out,
               "\nMisses by cause (fully visible frames not accepted on the ball; "
               "tracking_run.hpp FrameRecord::miss_cause)\n");
  auto print = [&](const std::string& name, const std::map<std::string, long>& causes) {
    std::fprintf(out, "%-22s", name.c_str());
    for (const auto& [cause, n] : causes) std::fprintf(out, " %s=%ld", cause.c_str(), n);
    std::fprintf(out, "\n");
  };
  for (const auto& [scene, causes] : by_scene) print(scene, causes);
  print("all scenes", total);
}

}  // namespace

SceneFigures add_up(const std::vector<const RunResult*>& runs) {
  SceneFigures s;
  for (const RunResult* r : runs) {
    ++s.scenes;
    for (const FrameRecord& f : r->frames) {
      if (f.ball_fully_visible) {
        ++s.fully_visible;
        s.detected += f.raw_on_ball;
        s.accepted += f.accepted_on_ball;
      }
      if (f.no_ball_in_view) {
        ++s.no_ball;
        s.false_accepted += f.accepted;
      }
    }
  }
  return s;
}

void print_scene_report(std::FILE* out, const std::vector<RunResult>& runs,
                        const std::vector<simulator::RandomScene>& scenes) {
  std::fprintf(out,
               "\nRandomised scenes (detect %% = the detector's pair on the ball, accept %% = the "
               "tracker accepting it, both over frames with the whole ball in view in both eyes; "
               "false acc %% = accepted over frames with no ball in view)\n");
  print_header(out, "scene");
  std::vector<const RunResult*> all;
  for (std::size_t i = 0; i < runs.size() && i < scenes.size(); ++i) {
    all.push_back(&runs[i]);
    const auto& l = scenes[i].labels;
    print_row(out, runs[i].scenario, add_up({&runs[i]}));
    std::fprintf(out,
                 "%-22s   d=%.3f m %s %s, floor %s, contrast %s (dE %.0f), distractors %s, "
                 "leave %s\n",
                 "", scenes[i].ball_diameter_m, l.ball_colour.c_str(), l.pattern.c_str(),
                 l.floor.c_str(), l.contrast.c_str(), l.contrast_delta_e, l.distractors.c_str(),
                 l.leave_view.c_str());
  }
  for (std::size_t c = 0; c < simulator::kCategoryNames.size(); ++c) {
    std::map<std::string, std::vector<const RunResult*>> groups;
    for (std::size_t i = 0; i < runs.size() && i < scenes.size(); ++i)
      groups[simulator::category_value(scenes[i].labels, c)].push_back(&runs[i]);
    std::fprintf(out, "\nby %s\n", simulator::kCategoryNames[c]);
    print_header(out, simulator::kCategoryNames[c]);
    for (const auto& [value, group] : groups) print_row(out, value, add_up(group));
  }
  std::fprintf(out, "\n");
  print_header(out, "");
  print_row(out, "TOTAL", add_up(all));
  std::fprintf(out, "(targets: detect >= 95 %% in every category, false acc < 1 %%)\n");
  print_miss_causes(out, runs);
}

}  // namespace stereoball::bench_tracking
