// stereoball-bench-tracking: runs simulator scenarios through the ball detector pipeline and
// the tracker core offline (no DDS, simulated time) and prints the figures of issue 6:
// false detections with no ball, track acceptance and 3D error with the ball visible, and the
// detector's time per stereo frame. Prints figures only; never asserts a target.

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/util/install_layout.hpp"
#include "common/util/result.hpp"
#include "loop_cli.hpp"
#include "loop_config.hpp"
#include "run_each.hpp"
#include "scene_report.hpp"
#include "tracking_run.hpp"

namespace bt = stereoball::bench_tracking;
namespace sl = stereoball::sim_loop;
using stereoball::bench_tracking::print_scene_report;

namespace {

struct Options {
  sl::LoopCli loop;
  std::string drive = "script";
  int threads = 1;
  int jobs = 1;
  std::string frames_csv;
  std::string png_dir;
  std::pair<std::int64_t, std::int64_t> png_frames{0, -1};
};

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball-bench-tracking: %s\n", message.c_str());
  return 2;
}

double pct(long part, long whole) {
  return whole ? 100.0 * part / whole : 0.0;
}

long count(const std::vector<bt::FrameRecord>& f,
           const std::function<bool(const bt::FrameRecord&)>& p) {
  return static_cast<long>(std::count_if(f.begin(), f.end(), p));
}

void print_absent(const std::vector<bt::RunResult>& runs) {
  std::printf("\nBall absent (clutter only): false detections before and after the tracker\n");
  std::printf("%-22s %7s %14s %16s %22s\n", "scenario", "frames", "raw detect %",
              "tracker accept %", "accepted of raw % (<1)");
  long frames = 0, raw = 0, acc = 0;
  for (const auto& r : runs) {
    if (r.frames.empty() || r.frames.front().ball_present) continue;
    const long n = static_cast<long>(r.frames.size());
    const long nr = count(r.frames, [](auto& f) { return f.raw_found; });
    const long na = count(r.frames, [](auto& f) { return f.raw_found && f.accepted; });
    std::printf("%-22s %7ld %14.2f %16.2f %22.2f\n", r.scenario.c_str(), n, pct(nr, n), pct(na, n),
                pct(na, nr));
    frames += n, raw += nr, acc += na;
  }
  if (frames == 0) std::printf("(no ball-absent scenario run)\n");
}

void print_visible(const std::vector<bt::RunResult>& runs) {
  std::printf(
      "\nBall present and visible in both eyes (on ball = triangulated centre within one ball "
      "radius of the truth)\n");
  std::printf("%-22s %7s %12s %16s %18s %10s %14s\n", "scenario", "visible", "raw on ball %",
              "track accept %", "accept on ball %", "off-ball", "off-ball acc");
  long vis = 0, on = 0, acc = 0, acc_on = 0;
  for (const auto& r : runs) {
    if (r.frames.empty() || !r.frames.front().ball_present) continue;
    const long n = count(r.frames, [](auto& f) { return f.ball_visible; });
    const long no = count(r.frames, [](auto& f) { return f.ball_visible && f.raw_on_ball; });
    const long na = count(r.frames, [](auto& f) { return f.ball_visible && f.accepted; });
    const long nao = count(r.frames, [](auto& f) { return f.ball_visible && f.accepted_on_ball; });
    const long off = count(r.frames, [](auto& f) { return f.raw_found && !f.raw_on_ball; });
    const long off_acc =
        count(r.frames, [](auto& f) { return f.raw_found && !f.raw_on_ball && f.accepted; });
    std::printf("%-22s %7ld %12.2f %16.2f %18.2f %10ld %14ld\n", r.scenario.c_str(), n, pct(no, n),
                pct(na, n), pct(nao, n), off, off_acc);
    vis += n, on += no, acc += na, acc_on += nao;
  }
  std::printf("%-22s %7ld %12.2f %16.2f %18.2f   (target: track accept >= 98%%)\n", "ALL", vis,
              pct(on, vis), pct(acc, vis), pct(acc_on, vis));
}

void print_error(const std::vector<bt::RunResult>& runs) {
  struct Bucket {
    const char* name;
    double lo_m, hi_m, target_pct;
  };
  const Bucket buckets[] = {{"1 m (0.8-1.2)", 0.8, 1.2, 0.1},
                            {"2 m (1.8-2.2)", 1.8, 2.2, 0.5},
                            {"all distances", 0.0, 1e9, -1.0}};
  std::printf("\n3D error of on-ball detections vs ground truth (all scenarios)\n");
  std::printf("%-16s %7s %11s %9s %11s %9s %9s\n", "distance", "frames", "median mm", "median %",
              "p95 mm", "p95 %", "target %");
  for (const auto& b : buckets) {
    std::vector<double> mm, rel;
    double sum[3] = {0, 0, 0};
    for (const auto& r : runs)
      for (const auto& f : r.frames)
        if (f.error_m >= 0 && f.true_distance_m >= b.lo_m && f.true_distance_m < b.hi_m) {
          mm.push_back(f.error_m * 1e3);
          rel.push_back(100.0 * f.error_m / f.true_distance_m);
          for (int i = 0; i < 3; ++i) sum[i] += f.error_xyz_m[i] * 1e3;
        }
    const double n = mm.empty() ? 1.0 : static_cast<double>(mm.size());
    char target[16] = "-";
    if (b.target_pct > 0) std::snprintf(target, sizeof(target), "<=%.1f", b.target_pct);
    std::printf("%-16s %7zu %11.1f %9.2f %11.1f %9.2f %9s   %+.1f / %+.1f / %+.1f\n", b.name,
                mm.size(), sl::percentile(mm, 0.5), sl::percentile(rel, 0.5),
                sl::percentile(mm, 0.95), sl::percentile(rel, 0.95), target, sum[0] / n, sum[1] / n,
                sum[2] / n);
  }
}

// The same times by the search that answered each frame (a tracked ball's predicted outlines,
// the prior's box, the whole frame, its radius bands): where the time goes.
void print_time_by_search(const std::vector<bt::RunResult>& runs) {
  std::map<std::string, std::vector<double>> cpu;
  for (const auto& r : runs)
    for (const auto& f : r.frames) cpu[f.search].push_back(f.cpu_ms);
  std::printf("%-22s %7s %13s %10s\n", "by search answering", "frames", "CPU median ms",
              "CPU p95 ms");
  for (auto& [search, ms] : cpu)
    std::printf("%-22s %7zu %13.2f %10.2f\n", search.c_str(), ms.size(), sl::percentile(ms, 0.5),
                sl::percentile(ms, 0.95));
}

void print_time(const std::vector<bt::RunResult>& runs, int threads, int jobs) {
  std::printf(
      "\nDetector time per stereo frame (640x480 raw, rectification included, %d OpenCV "
      "thread(s))\n",
      threads);
  if (jobs > 1)
    std::printf("(%d scenes ran at once: these times share the machine, not one-core figures)\n",
                jobs);
  std::printf("%-22s %7s %13s %10s %14s %11s\n", "scenario", "frames", "CPU median ms",
              "CPU p95 ms", "wall median ms", "wall p95 ms");
  std::vector<double> all_cpu, all_wall;
  for (const auto& r : runs) {
    std::vector<double> cpu, wall;
    for (const auto& f : r.frames) cpu.push_back(f.cpu_ms), wall.push_back(f.wall_ms);
    all_cpu.insert(all_cpu.end(), cpu.begin(), cpu.end());
    all_wall.insert(all_wall.end(), wall.begin(), wall.end());
    std::printf("%-22s %7zu %13.2f %10.2f %14.2f %11.2f\n", r.scenario.c_str(), cpu.size(),
                sl::percentile(cpu, 0.5), sl::percentile(cpu, 0.95), sl::percentile(wall, 0.5),
                sl::percentile(wall, 0.95));
  }
  std::printf("%-22s %7zu %13.2f %10.2f %14.2f %11.2f   (target: median <= 5 ms)\n", "ALL",
              all_cpu.size(), sl::percentile(all_cpu, 0.5), sl::percentile(all_cpu, 0.95),
              sl::percentile(all_wall, 0.5), sl::percentile(all_wall, 0.95));
  print_time_by_search(runs);
}

// Quotes a CSV field (RFC 4180): reasons may hold commas.
std::string csv_field(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// One row per frame of every run: what was true, what was found, what the tracker said.
stereoball::Status write_frames_csv(std::FILE* f, const std::string& path,
                                    const std::vector<bt::RunResult>& runs) {
  std::fprintf(f,
               "scenario,frame,stamp_ns,visible,true_x_px,true_y_px,found,on_ball,found_x_px,"
               "found_y_px,found_r_px,status,reason,verdict,verdict_reason,accepted,state,error_mm,"
               "fully_visible,true_r_px,truth_coverage,miss_cause,left_dx_px,left_dy_px,left_dr_px,"
               "right_dx_px,right_dy_px,right_dr_px,search,cpu_ms\n");
  for (const auto& r : runs) {
    for (size_t i = 0; i < r.frames.size(); ++i) {
      const auto& fr = r.frames[i];
      std::fprintf(
          f,
          "%s,%zu,%lld,%d,%.2f,%.2f,%d,%d,%.2f,%.2f,%.2f,%s,%s,%s,%s,%d,%s,%.2f,%d,%.1f,%."
          "2f,%s,%.3f,%."
          "3f,%.3f,%.3f,%.3f,%.3f,%s,%.3f\n",
          r.scenario.c_str(), i, static_cast<long long>(fr.stamp_ns), fr.ball_visible,
          fr.true_left_x_px, fr.true_left_y_px, fr.raw_found, fr.raw_on_ball, fr.found_left_x_px,
          fr.found_left_y_px, fr.found_radius_px, fr.detection_status.c_str(),
          csv_field(fr.detection_reason).c_str(), fr.verdict.c_str(),
          csv_field(fr.verdict_reason).c_str(), fr.accepted, fr.track_state.c_str(),
          fr.error_m >= 0 ? fr.error_m * 1e3 : -1.0, fr.ball_fully_visible, fr.true_radius_px,
          fr.truth_coverage, fr.miss_cause.c_str(), fr.outline_error_left_px[0],
          fr.outline_error_left_px[1], fr.outline_error_left_px[2], fr.outline_error_right_px[0],
          fr.outline_error_right_px[1], fr.outline_error_right_px[2], fr.search.c_str(), fr.cpu_ms);
    }
  }
  const bool ok = std::fflush(f) == 0 && !std::ferror(f);
  std::fclose(f);
  if (!ok) return stereoball::Error{"cannot write '" + path + "': " + std::strerror(errno)};
  return {};
}

// Scenario si of selected, with its frames written as PNG where asked.
stereoball::Result<bt::RunResult> run_one(const sl::LoopSelection& selected, std::size_t si,
                                          const Options& o, bt::Drive drive) {
  const auto& scenario = selected.scenarios[si];
  bt::RunConfig config = sl::config_for(selected, si);
  config.drive = drive;
  config.seconds = sl::run_seconds(o.loop, scenario);
  std::string png_error;
  auto dump = [&](std::int64_t i, const sl::LoopFrame& f) {
    if (o.png_dir.empty() || i < o.png_frames.first || i > o.png_frames.second) return;
    for (const auto& [eye, image] : {std::pair{"left", &f.left_raw}, {"right", &f.right_raw}}) {
      const std::string path = cv::format("%s/%s_%s_%06lld.png", o.png_dir.c_str(),
                                          scenario.name.c_str(), eye, static_cast<long long>(i));
      if (png_error.empty() && !cv::imwrite(path, *image)) png_error = "cannot write " + path;
    }
  };
  auto out = bt::run_scenario(config, dump);
  if (!png_error.empty()) return stereoball::Error{png_error};
  if (!out.error.empty()) return stereoball::Error{out.error};
  std::fprintf(stderr, "  %s: %zu frames\n", out.result.scenario.c_str(), out.result.frames.size());
  return std::move(out.result);
}

// Every selected scenario, o.jobs at a time (each run is independent: its own simulator,
// pipeline and tracker), in selection order (sim_loop::run_each).
stereoball::Result<std::vector<bt::RunResult>> run_all(const sl::LoopSelection& selected,
                                                       const Options& o, bt::Drive drive) {
  std::vector<bt::RunResult> runs(selected.scenarios.size());
  const auto status = sl::run_each(runs.size(), o.jobs, [&](std::size_t si) -> stereoball::Status {
    auto r = run_one(selected, si, o, drive);
    if (!r) return stereoball::Error{r.error()};
    runs[si] = std::move(r).value();
    return {};
  });
  if (!status) return stereoball::Error{status.error()};
  return runs;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball-bench-tracking: offline detection + tracking benchmark on simulator scenarios.\n"
      "Renders each scenario with the simulator core (simulated time), runs the ball detector\n"
      "pipeline (LUT rectification, Pixel-to-Pixel on both eyes, pairing, triangulation) and the\n"
      "tracker core on every frame, compares with the ground truth and prints: false detections\n"
      "with no ball, track acceptance and 3D error with the ball visible, detector time.\n"
      "No DDS; figures only, no pass/fail."};
  Options o;
  o.loop.config_dir = stereoball::paths::shipped_config_dir();
  sl::add_loop_options(app, o.loop);
  app.add_option("--drive", o.drive,
                 "who drives the robot: script (the scenario's commands) or controller (the "
                 "motion controller core on the tracker's output)")
      ->check(CLI::IsMember({"script", "controller"}))
      ->capture_default_str();
  app.add_option("--threads", o.threads, "OpenCV threads (1 = one core, the target)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--jobs", o.jobs,
                 "scenes run at once, each on a thread of its own (the figures are the same; "
                 "the times are then not one-core times)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  app.add_option("--frames-csv", o.frames_csv,
                 "also write one CSV row per frame (truth, detection, reason, tracker verdict)");
  app.add_option("--png-dir", o.png_dir,
                 "write the raw frames of --png-frames as SCENARIO_left_NNNNNN.png / _right_ here");
  app.add_option("--png-frames", o.png_frames, "FIRST:LAST, the frames written to --png-dir")
      ->delimiter(':');
  CLI11_PARSE(app, argc, argv);
  if (!o.png_dir.empty() && o.png_frames.second < o.png_frames.first)
    return fail("--png-dir needs --png-frames FIRST:LAST with FIRST <= LAST");
  cv::setNumThreads(o.threads);

  auto selected = sl::select_runs(o.loop);
  if (!selected) return fail(selected.error());
  // Opened before the (long) runs so a bad path fails at once.
  std::FILE* csv = nullptr;
  if (!o.frames_csv.empty()) {
    csv = std::fopen(o.frames_csv.c_str(), "w");
    if (!csv) return fail("cannot write '" + o.frames_csv + "': " + std::strerror(errno));
  }
  const bt::Drive drive = o.drive == "controller" ? bt::Drive::kController : bt::Drive::kScript;
  const bt::RunConfig& base = selected->base;

  std::printf("stereoball-bench-tracking: %zu scenario(s), %dx%d at %.1f Hz, drive %s%s\n",
              selected->scenarios.size(), base.sim.width_px, base.sim.height_px,
              base.sim.frame_rate_hz, o.drive.c_str(),
              o.loop.plain ? ", plain room and one-colour ball" : "");
  const auto ran = run_all(*selected, o, drive);
  if (!ran) return fail(ran.error());
  const std::vector<bt::RunResult>& runs = ran.value();
  if (!selected->random.empty()) print_scene_report(stdout, runs, selected->random);
  print_absent(runs);
  print_visible(runs);
  print_error(runs);
  print_time(runs, o.threads, o.jobs);
  if (csv) {
    if (auto e = write_frames_csv(csv, o.frames_csv, runs); !e) return fail(e.error());
    std::fprintf(stderr, "  per-frame CSV: %s\n", o.frames_csv.c_str());
  }
  return 0;
}
