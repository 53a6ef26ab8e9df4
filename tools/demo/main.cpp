// stereoball demo: runs the whole system on the simulator (simulator, ball_detector, tracker,
// motion_controller as separate processes), shows progress, scores the run against the
// simulator's ground truth and writes a report (summary, plots, log) to --out.

#include <signal.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <opencv2/imgcodecs.hpp>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/install_layout.hpp"
#include "common/util/log.hpp"
#include "installed_profile.hpp"
#include "metrics.hpp"
#include "motion_controller/node/command_msg.hpp"
#include "motion_controller/node/controller_params_file.hpp"
#include "plot.hpp"
#include "supervisor.hpp"
#include "viewer_process.hpp"

namespace sb = stereoball;
namespace fs = std::filesystem;
using sb::demo::TrackState;

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int) {
  g_stop = true;
}

struct Recorded {
  std::vector<sb::demo::TruthSample> truth;
  std::vector<sb::demo::DetectionSample> detections;
  std::vector<sb::demo::TrackSample> tracks;
  std::vector<std::pair<double, double>> commands;  // (linear, angular)
};

const char* state_name(TrackState s) {
  return s == TrackState::kFollowing   ? "FOLLOWING"
         : s == TrackState::kSearching ? "SEARCHING"
                                       : "IDLE";
}

bool accepted(stereoball_msg_TrackVerdict v) {
  return v == stereoball_msg_VERDICT_STARTUP_ACCEPTED ||
         v == stereoball_msg_VERDICT_BLOCK_MATCH_ACCEPTED ||
         v == stereoball_msg_VERDICT_STATISTICS_ACCEPTED;
}

struct Readers {
  explicit Readers(sb::dds::DomainParticipant& p)
      : truth(p, sb::topics::kGroundTruth),
        detection(p, sb::topics::kBallDetection),
        track(p, sb::topics::kBallTrack),
        command(p, sb::topics::kVelocityCommand) {}
  sb::dds::DataReader<stereoball_msg_GroundTruth> truth;
  sb::dds::DataReader<stereoball_msg_BallDetection> detection;
  sb::dds::DataReader<stereoball_msg_BallTrack> track;
  sb::dds::DataReader<stereoball_msg_VelocityCommand> command;
};

void drain(Readers& r, Recorded& rec) {
  for (auto& s : r.truth.take(256)) {
    sb::demo::TruthSample t;
    t.seq = s->frame_seq;
    t.t_s = s->sim_time_s;
    t.ball_present = s->ball_present;
    t.visible = s->ball_visible_left && s->ball_visible_right;
    for (int i = 0; i < 3; ++i) t.ball_cam_m[i] = s->ball_camera_m[i];
    t.ball_world_m[0] = s->ball_world_m[0];
    t.ball_world_m[1] = s->ball_world_m[1];
    t.robot_world_m[0] = s->robot_x_m;
    t.robot_world_m[1] = s->robot_y_m;
    t.robot_yaw_rad = s->robot_yaw_rad;
    rec.truth.push_back(t);
  }
  for (auto& s : r.detection.take(256)) {
    sb::demo::DetectionSample d;
    d.seq = s->frame_seq;
    d.found = s->status == stereoball_msg_DETECTION_FOUND;
    for (int i = 0; i < 3; ++i) d.position_m[i] = s->position_m[i];
    rec.detections.push_back(d);
  }
  for (auto& s : r.track.take(256)) {
    sb::demo::TrackSample t;
    t.seq = s->frame_seq;
    t.state = sb::motion_controller::from_msg(s->state);
    t.accepted = accepted(s->verdict);
    for (int i = 0; i < 3; ++i) t.position_m[i] = s->position_m[i];
    rec.tracks.push_back(t);
  }
  for (auto& s : r.command.take(256)) rec.commands.emplace_back(s->linear_mps, s->angular_radps);
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// Each leave event as two vertical lines: the track going SEARCHING (with the side searched and
// the side the ball left by) and the track following again.
std::vector<sb::demo::Marker> event_markers(const std::vector<sb::demo::LeaveEvent>& events) {
  std::vector<sb::demo::Marker> out;
  for (const auto& e : events) {
    out.push_back({e.t_s,
                   std::string("lost: searches ") + sb::demo::side_name(e.searched) +
                       " (ball went " + sb::demo::side_name(e.ball_side) + ")",
                   cv::Scalar(0, 0, 210)});
    if (e.reacquired) {
      out.push_back({e.reacquired_t_s, "reacquired after " + fmt("%.2f s", e.reacquire_s),
                     cv::Scalar(0, 150, 0)});
    }
  }
  return out;
}

void write_plots(const fs::path& out, const std::string& scenario, const Recorded& rec,
                 double target_m, const std::vector<sb::demo::LeaveEvent>& events) {
  using sb::demo::Chart;
  using sb::demo::Series;
  const auto markers = event_markers(events);
  Chart top{"top view: " + scenario, "x (m)", "y (m)", {}, true, {}, {}};
  Series robot{"robot", {}, cv::Scalar(200, 80, 0)}, ball{"ball", {}, cv::Scalar(0, 120, 255)};
  for (const auto& t : rec.truth) {
    robot.points.emplace_back(t.robot_world_m[0], t.robot_world_m[1]);
    if (t.ball_present) ball.points.emplace_back(t.ball_world_m[0], t.ball_world_m[1]);
  }
  // Where the robot was when the track lost the ball and when it followed it again.
  Series lost{"robot at loss", {}, cv::Scalar(0, 0, 210), false, true};
  Series found{"at reacquisition", {}, cv::Scalar(0, 150, 0), false, true};
  for (const auto& e : events) {
    for (const auto& t : rec.truth) {
      if (t.t_s == e.t_s) lost.points.emplace_back(t.robot_world_m[0], t.robot_world_m[1]);
      if (e.reacquired && t.t_s == e.reacquired_t_s)
        found.points.emplace_back(t.robot_world_m[0], t.robot_world_m[1]);
    }
  }
  top.series = {robot, ball, lost, found};
  cv::imwrite((out / (scenario + "_topview.png")).string(), sb::demo::render(top, {700, 700}));

  Chart dist{"distance to ball", "time (s)", "m", {}, false, {}, markers};
  Chart bearing{"bearing of ball (+ = right)", "time (s)", "deg", {}, false, {}, markers};
  Series d_true{"truth", {}, cv::Scalar(0, 120, 255)},
      d_target{"target", {}, cv::Scalar(0, 160, 0)};
  Series b_true{"truth", {}, cv::Scalar(0, 120, 255)};
  for (const auto& t : rec.truth) {
    if (!t.ball_present) continue;
    // From the robot's centre and heading: what the controller's target refers to.
    d_true.points.emplace_back(t.t_s, sb::demo::robot_ball_distance_m(t));
    d_target.points.emplace_back(t.t_s, target_m);
    b_true.points.emplace_back(t.t_s, sb::demo::robot_ball_bearing_rad(t) * 180 / M_PI);
  }
  dist.series = {d_true, d_target};
  bearing.series = {b_true};
  cv::imwrite((out / (scenario + "_distance_bearing.png")).string(),
              sb::demo::render_stack({dist, bearing}, {900, 300}));

  std::map<uint64_t, double> t_of_seq;
  for (const auto& t : rec.truth) t_of_seq[t.seq] = t.t_s;
  Chart states{"track state and ball visibility",  "time (s)", "", {}, false,
               {"IDLE", "FOLLOWING", "SEARCHING"}, markers};
  Series state{"track state", {}, cv::Scalar(200, 0, 120), true};
  Series visible{"ball visible", {}, cv::Scalar(0, 160, 0), true};
  for (const auto& tr : rec.tracks) {
    if (!t_of_seq.count(tr.seq)) continue;
    state.points.emplace_back(t_of_seq[tr.seq], static_cast<double>(tr.state));
  }
  for (const auto& t : rec.truth) visible.points.emplace_back(t.t_s, t.visible ? 1.1 : -0.1);
  std::sort(state.points.begin(), state.points.end(), [](auto& a, auto& b) { return a.x < b.x; });
  states.series = {state, visible};
  cv::imwrite((out / (scenario + "_state.png")).string(), sb::demo::render(states, {900, 300}));
}

// One summary cell: the events' values, comma-separated ("-" for none).
std::string joined(const std::vector<sb::demo::LeaveEvent>& events,
                   const std::function<std::string(const sb::demo::LeaveEvent&)>& cell) {
  std::string out;
  for (const auto& e : events) out += (out.empty() ? "" : ", ") + cell(e);
  return out.empty() ? "-" : out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball demo: the whole system on the simulator, scored against ground truth"};
  std::vector<std::string> scenarios;
  double duration_s = 20, rate = 1.0;
  std::string out_dir = "demo-out";
  int domain = sb::dds::domain_from_env(0);
  app.add_option("-s,--scenario", scenarios,
                 "scenario(s) from config/scenarios (default: ball_rolling_away, "
                 "ball_kicked_past_right, no_ball)");
  app.add_option("-d,--duration", duration_s, "simulated seconds per scenario")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  app.add_option("-o,--out", out_dir, "report folder (created)")->capture_default_str();
  app.add_option("--domain", domain, "DDS domain")
      ->check(CLI::Range(0, 232))
      ->capture_default_str();
  app.add_option("--rate", rate, "simulation speed (1 = real time)")
      ->check(CLI::Range(0.1, 10.0))
      ->capture_default_str();
  bool view = false;
  int view_port = 8765;
  std::string view_bind = "127.0.0.1";
  app.add_flag("--view", view, "open the live viewer (stereoball view) on the demo");
  app.add_option("--view-port", view_port, "viewer port")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  app.add_option("--view-bind", view_bind, "viewer address (0.0.0.0 = reachable from the LAN)")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (scenarios.empty()) scenarios = {"ball_rolling_away", "ball_kicked_past_right", "no_ball"};
  sb::log::init("demo");
  const fs::path scenarios_dir = sb::paths::shipped_config_path("scenarios");
  for (const auto& s : scenarios) {
    if (!fs::exists(scenarios_dir / (s + ".yaml"))) {
      std::fprintf(stderr, "stereoball demo: unknown scenario '%s' (see config/scenarios/)\n",
                   s.c_str());
      return 2;
    }
  }
  auto profile = sb::launch::load_profile_for_this_program("all-in-one");
  if (!profile) {
    std::fprintf(stderr, "stereoball demo: %s\n", profile.error().c_str());
    return 2;
  }
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) {
    std::fprintf(stderr, "stereoball demo: cannot create %s: %s\n", out_dir.c_str(),
                 ec.message().c_str());
    return 2;
  }
  // The target distance the metrics judge against is the controller's own, loaded as the
  // motion_controller process loads it (a missing or bad file is an error, not a default).
  const auto controller = sb::motion_controller::load_controller_params(
      sb::paths::shipped_config_path("motion_controller.yaml"));
  if (!controller) {
    std::fprintf(stderr, "stereoball demo: %s\n", controller.error().c_str());
    return 2;
  }
  const double target_m = controller->controller.target_distance_m;
  if (!profile->cyclonedds_config.empty() && !std::getenv("CYCLONEDDS_URI")) {
    setenv("CYCLONEDDS_URI", ("file://" + profile->cyclonedds_config).c_str(), 1);
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const fs::path log_path = fs::path(out_dir) / "stereoball.log";
  const bool tty = isatty(STDOUT_FILENO);
  std::vector<sb::demo::ScenarioMetrics> results;
  std::vector<std::vector<sb::demo::LeaveEvent>> leaves;  // per scenario, parallel to results
  bool nodes_ok = true;
  std::unique_ptr<sb::demo::ViewerProcess> viewer;
  if (view) {
    // One viewer for every scenario: its partition pattern matches each scenario's partition.
    viewer = std::make_unique<sb::demo::ViewerProcess>(
        fs::read_symlink("/proc/self/exe").parent_path().string(), domain,
        "demo." + std::to_string(getpid()) + ".*", view_bind, view_port, log_path.string());
    if (!viewer->running()) {
      std::fprintf(stderr, "stereoball demo: %s\n", viewer->error().c_str());
      return 2;
    }
    std::printf("viewer: http://%s:%d/ (open it in a browser; Foxglove: ws://%s:%d/)\n",
                view_bind.c_str(), view_port, view_bind.c_str(), view_port);
    std::fflush(stdout);
  }

  for (const auto& scenario : scenarios) {
    if (g_stop) break;
    const std::string partition = "demo." + std::to_string(getpid()) + "." + scenario;
    sb::launch::SupervisorOptions options;
    options.bin_dir = fs::read_symlink("/proc/self/exe").parent_path().string();
    options.log_path = log_path.string();
    options.extra_args = {"--domain", std::to_string(domain), "--partition", partition};
    options.node_args["simulator"] = {"--scenario", scenario, "--rate", fmt("%g", rate)};
    std::printf("== %s (%.0f s simulated) ==\n", scenario.c_str(), duration_s);
    sb::dds::DomainParticipant participant({domain, partition});
    Readers readers(participant);
    Recorded rec;
    sb::launch::Supervisor supervisor(*profile, options,
                                      [](const std::string& e) { sb::log::info(e); });
    if (auto started = supervisor.start_all(sb::node::monotonic_ns()); !started) {
      std::fprintf(stderr, "stereoball demo: %s\n", started.error().c_str());
      return 2;
    }
    const int64_t start = sb::node::monotonic_ns();
    // Wall-clock deadline: simulated time plus start-up margin, so a stalled system still ends.
    const int64_t deadline = start + static_cast<int64_t>((duration_s / rate + 30) * 1e9);
    int64_t next_print = start;
    size_t frames_at_print = 0;
    double sim_t = 0;
    while (!g_stop && sim_t < duration_s && sb::node::monotonic_ns() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      drain(readers, rec);
      supervisor.poll(sb::node::monotonic_ns());
      if (!rec.truth.empty()) sim_t = rec.truth.back().t_s;
      const int64_t now = sb::node::monotonic_ns();
      if (now >= next_print) {
        const double fps = (rec.truth.size() - frames_at_print) / (next_print == start ? 1.0 : 0.5);
        frames_at_print = rec.truth.size();
        next_print = now + 500'000'000;
        const char* st = rec.tracks.empty() ? "-" : state_name(rec.tracks.back().state);
        const double dist = rec.truth.empty() || !rec.truth.back().ball_present
                                ? NAN
                                : sb::demo::robot_ball_distance_m(rec.truth.back());
        std::printf(
            "%s  t=%5.1f s  %5.1f fps  track %-9s  ball %s  detections %zu  cmd %+.2f m/s %+.2f "
            "rad/s%s",
            tty ? "\r" : "", sim_t, fps, st,
            std::isnan(dist) ? "  absent" : fmt("%5.2f m", dist).c_str(), rec.detections.size(),
            rec.commands.empty() ? 0.0 : rec.commands.back().first,
            rec.commands.empty() ? 0.0 : rec.commands.back().second, tty ? "   " : "\n");
        std::fflush(stdout);
      }
    }
    if (tty) std::printf("\n");
    const bool clean = supervisor.stop_all();
    drain(readers, rec);
    for (const auto& st : supervisor.states()) {
      if (st.given_up || st.restarts > 0) {
        nodes_ok = false;
        std::printf("  node %s: %d restarts, last exit code %d\n", st.name.c_str(), st.restarts,
                    st.last_exit_code);
      }
    }
    if (!clean) std::printf("  (some nodes did not stop cleanly; see %s)\n", log_path.c_str());
    if (rec.truth.empty()) {
      std::printf("  no ground truth received: the simulator did not run (see %s)\n",
                  log_path.c_str());
      nodes_ok = false;
    }
    sb::demo::MetricsParams params;
    params.target_distance_m = target_m;
    results.push_back(sb::demo::score(scenario, rec.truth, rec.detections, rec.tracks, params));
    leaves.push_back(sb::demo::leave_events(rec.truth, rec.tracks));
    write_plots(out_dir, scenario, rec, target_m, leaves.back());
  }

  std::ofstream md(fs::path(out_dir) / "summary.md");
  md << "# StereoBall demo summary\n\n| scenario | frames | visible | detection rate | false "
        "detections | "
        "false-accept rate | track accepted (visible) | 3D error median (m) | p95 (m) | rel. "
        "median | "
        "losses | reacquired | reacquire median (s) | distance error following (m) | within "
        "tolerance |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& m : results) {
    md << "| " << m.scenario << " | " << m.frames << " | " << m.visible_frames << " | "
       << fmt("%.3f", m.detection_rate) << " | " << m.false_detections << " | "
       << fmt("%.3f", m.false_accept_rate) << " | " << fmt("%.3f", m.accept_rate_visible) << " | "
       << fmt("%.4f", m.error_median_m) << " | " << fmt("%.4f", m.error_p95_m) << " | "
       << fmt("%.4f", m.error_median_rel) << " | " << m.losses << " | " << m.reacquired << " | "
       << (m.reacquire_median_s < 0 ? std::string("-") : fmt("%.2f", m.reacquire_median_s)) << " | "
       << fmt("%.3f", m.following_distance_error_m) << " | " << fmt("%.3f", m.within_tolerance)
       << " |\n";
  }
  // The paper's predictive search: every time the track went SEARCHING.
  md << "\n## Leave events\n\nThe track going from FOLLOWING to SEARCHING; searched = the way the "
        "robot turned while searching, ball left by = the side of the view the ball was on when "
        "last visible (both from the simulator's ground truth); reacquired = the track following "
        "again, seconds after the leave.\n\n"
        "| scenario | leave events | lost at (s) | searched | ball left by | searched the ball's "
        "side | reacquired after (s) |\n|---|---|---|---|---|---|---|\n";
  for (size_t i = 0; i < results.size(); ++i) {
    const auto& ev = leaves[i];
    md << "| " << results[i].scenario << " | " << ev.size() << " | "
       << joined(ev, [](const auto& e) { return fmt("%.2f", e.t_s); }) << " | "
       << joined(ev, [](const auto& e) { return std::string(sb::demo::side_name(e.searched)); })
       << " | "
       << joined(ev, [](const auto& e) { return std::string(sb::demo::side_name(e.ball_side)); })
       << " | "
       << joined(ev,
                 [](const auto& e) { return std::string(e.searched_ball_side() ? "yes" : "no"); })
       << " | "
       << joined(ev,
                 [](const auto& e) {
                   return e.reacquired ? fmt("%.2f", e.reacquire_s) : std::string("never");
                 })
       << " |\n";
  }
  md << "\nPlots: `<scenario>_topview.png`, `<scenario>_distance_bearing.png`, "
        "`<scenario>_state.png` (leave events as dashed lines: red = lost, green = reacquired). "
        "Log of every node: `stereoball.log`.\n";
  md.close();
  std::printf("\n");
  std::ifstream again(fs::path(out_dir) / "summary.md");
  std::printf("%s", std::string(std::istreambuf_iterator<char>(again), {}).c_str());
  std::printf("\nreport written to %s/\n", out_dir.c_str());
  return nodes_ok ? 0 : 1;
}
