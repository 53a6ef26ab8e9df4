// stereoball bench chaos --minutes N [--seed S] [--json FILE]: the whole system on the simulator
// (simulator, ball_detector, tracker, motion_controller as processes, the robot side and the
// workstation side in two network namespaces when `ip netns` works here) follows the ball while
// seeded faults hit it: nodes killed and restarted, the link cut, garbage on stereo/frame, the
// deployment key rotated, the e-stop engaged, commands signed with an unknown key. Afterwards
// the simulator's base log, the run's timeline, `stereoball record`'s file and /proc memory
// samples are judged by chaos_checks (exit 1 when a check fails).
// This file: the command line and the signals; the run is chaos_run.hpp's Run, the child modes
// (flood, rogue) are in chaos_children.hpp.
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "chaos_children.hpp"
#include "chaos_processes.hpp"
#include "chaos_run.hpp"
#include "common/util/cli11.hpp"

namespace bc = stereoball::bench_chaos;

namespace {

// SIGINT / SIGTERM: the run stops its faults, stops the nodes and judges what it has.
void on_signal(int) {
  bc::g_stop = 1;
}

// The flags of the command line (README.md), into o.
void add_flags(CLI::App& app, bc::Options& o) {
  app.add_option("--minutes", o.minutes, "length of the run, minutes")
      ->check(CLI::Range(0.5, 24 * 60.0))
      ->capture_default_str();
  app.add_option("--seed", o.seed, "seed of the fault schedule")->capture_default_str();
  app.add_option("--json", o.json_path, "write the results as JSON to this file");
  app.add_option("--out-dir", o.out_dir,
                 "keys, base log, recording and node logs (default: a new folder in /tmp)");
  app.add_option("--bin-dir", o.bin_dir, "where the programs are (default: beside this one)");
  app.add_option("--scenario", o.scenario, "simulator scenario (looped)")->capture_default_str();
  app.add_option("--mean-gap", o.mean_gap_s, "mean quiet time between faults, s")
      ->check(CLI::Range(0.5, 3600.0))
      ->capture_default_str();
  app.add_option("--warmup", o.warmup_s,
                 "seconds before the first fault (and before memory "
                 "is first sampled in each process)")
      ->check(CLI::Range(1.0, 600.0))
      ->capture_default_str();
  app.add_flag("--one-round", o.one_round,
               "each fault kind once (the schedule's first round), then stop 10 s after the last "
               "fault ends; --minutes caps the run");
  app.add_flag("--no-netns", o.no_netns, "everything on one host (no link fault)");
  app.add_option("--memory-min-span", o.memory_min_span_s,
                 "judge the memory growth of process instances observed at least this long "
                 "after settling, s")
      ->capture_default_str();
  app.add_option("--memory-settle", o.memory_settle_s,
                 "memory is judged from this long after each start (the working set forms), s")
      ->check(CLI::Range(0.0, 3600.0))
      ->capture_default_str();
  app.add_option("--memory-max-growth", o.memory_max_growth_percent,
                 "largest memory growth allowed, percent")
      ->capture_default_str();
  app.add_option("--domain", o.domain, "DDS domain (default $STEREOBALL_DOMAIN or 0)");
  app.add_option("--partition", o.partition, "DDS partition (default $STEREOBALL_PARTITION)");
  app.add_option("--child", o.child, "")->check(CLI::IsMember({"flood", "rogue"}))->group("");
  app.add_option("--child-seconds", o.child_seconds, "")->group("");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball bench chaos: the whole system on the simulator follows the ball while seeded "
      "faults hit it (nodes killed and restarted, the link between two network namespaces cut, "
      "garbage on stereo/frame, the deployment key rotated, the e-stop engaged, commands signed "
      "with an unknown key). Checks: the robot never moved on stale or unauthenticated input, "
      "the e-stop held, memory per process, published vs recorded. Exit 1 when a check fails."};
  bc::Options o;
  if (const char* d = std::getenv("STEREOBALL_DOMAIN")) o.domain = std::atoi(d);
  if (const char* p = std::getenv("STEREOBALL_PARTITION")) o.partition = p;
  add_flags(app, o);
  CLI11_PARSE(app, argc, argv);

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  try {
    if (o.child == "flood") return bc::run_flood(o);
    if (o.child == "rogue") return bc::run_rogue(o);
    bc::Run run(o);
    return run.main();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereoball bench chaos: %s\n", e.what());
    return 2;
  }
}
