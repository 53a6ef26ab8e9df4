// stereoball bench latency: the whole system as separate processes (simulator, ball_detector,
// tracker, motion_controller), measured from each frame's exposure to the velocity command that
// answered it, stage by stage, for raw and JPEG frames at 30 and 60 Hz; on one host and, with
// --two-hosts, across two network namespaces (robot: simulator + motion_controller;
// workstation: ball_detector + tracker). Prints figures, --json FILE writes them; asserts
// nothing about them.

#include <signal.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/shared_memory.hpp"
#include "common/node/node_runner.hpp"
#include "latency_figures.hpp"
#include "real_stereo_set.hpp"
#include "two_host_system.hpp"

namespace sb = stereoball;
namespace sd = stereoball::distributed;
using namespace std::chrono_literals;

namespace {

struct Options {
  double seconds = 20, warmup_s = 6;
  int runs = 1, domain = 0;
  std::vector<std::string> encodings{"raw", "jpeg"};
  std::vector<int> rates_hz{30, 60};
  bool one_host = true, two_hosts = false, shared_memory = false;
  std::string scenario = "ball_rolling_across", json_path, one_host_cyclonedds, frames_csv;
  std::string source = "simulator";  // or "files": camera_server plays frames rendered first
  double file_seconds = 3;           // simulated seconds rendered to files (looped)
  std::string detector_override;     // --detector-config: YAML merged over the shipped file
  std::string detector_config;       // the file ball_detector reads (shipped, or composed)
  std::string detector_times;        // --detector-frame-times: ball_detector's stage times
  std::string workstation_profile = "workstation";  // two hosts: the vision namespace's profile
};

// One measured configuration.
struct Case {
  std::string setup, encoding;
  int rate_hz = 30;
  std::string key() const { return encoding + "_" + std::to_string(rate_hz) + "hz"; }
};

// The simulator's render lead: at its start, and its range over the run (when logged).
struct RenderLead {
  double start_ms = 0.0;
  std::optional<double> min_ms, max_ms;
};

struct Result {
  sd::LatencyFigures figures;  // frames exposed in the measured window
  sd::CoreLoad load;
  sd::LatencyFigures startup;           // frames exposed before it (start-up and warm-up)
  std::vector<sd::FrameStages> frames;  // every frame, for --frames-csv
  std::int64_t measured_from_ns = 0;
  std::map<std::string, sd::ProgramCpu> cpu;  // per program, per frame of the window
  std::optional<RenderLead> render_lead;      // the simulator's, from its log lines
};

// The simulator's render lead, ms: its start-up measurement ("frames rendered N us ahead") and
// the range the frames' own work gave it over the run ("render lead over the run: A to B us").
// A lead near the frame period puts the next frame's render (two threads) beside this frame's
// detection, so runs are compared with it.
std::optional<double> number_after(const std::string& text, const std::string& key) {
  const auto at = text.find(key);
  if (at == std::string::npos) return std::nullopt;
  try {
    return std::stod(text.substr(at + key.size(), 12));
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<RenderLead> render_lead(const std::string& launch_log) {
  const auto start_us = number_after(launch_log, "frames rendered ");
  if (!start_us) return std::nullopt;
  RenderLead lead{*start_us * 1e-3, std::nullopt, std::nullopt};
  const std::string key = "render lead over the run: ";
  const auto at = launch_log.find(key);
  long long min_us = 0, max_us = 0;
  if (at != std::string::npos &&
      std::sscanf(launch_log.c_str() + at + key.size(), "%lld to %lld", &min_us, &max_us) == 2) {
    lead.min_ms = static_cast<double>(min_us) * 1e-3;
    lead.max_ms = static_cast<double>(max_us) * 1e-3;
  }
  return lead;
}

void print_render_lead(const RenderLead& lead, int rate_hz) {
  std::printf("  simulator render lead %.1f ms at its start", lead.start_ms);
  if (lead.min_ms && lead.max_ms)
    std::printf(", %.1f-%.1f ms over the run (its frames' own render time)", *lead.min_ms,
                *lead.max_ms);
  std::printf(
      "; near the %.1f ms period, the next frame's render runs beside this frame's "
      "detection\n",
      1e3 / rate_hz);
}

void add_render_lead(const RenderLead& lead, nlohmann::json& j) {
  j["simulator_render_lead_ms"] = lead.start_ms;
  if (lead.min_ms && lead.max_ms) {
    j["simulator_render_lead_min_ms"] = *lead.min_ms;
    j["simulator_render_lead_max_ms"] = *lead.max_ms;
  }
}

// The figures of one run: the measured window's, and those of the frames before it apart.
Result result_of(const sd::ObserverLog& detection_log, const sd::ObserverLog& control_log,
                 std::int64_t from_ns, std::int64_t to_ns, int rate_hz, const sd::CoreLoad& load) {
  Result r;
  r.figures = sd::latency_figures(detection_log, control_log, from_ns, to_ns, rate_hz);
  r.load = load;
  r.startup = sd::latency_figures(detection_log, control_log, 0, from_ns, rate_hz);
  r.frames = sd::frame_stages(detection_log, control_log, 0, to_ns);
  r.measured_from_ns = from_ns;
  return r;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Sets the value of a top-level key of a shipped YAML text; false if the key is not there.
bool set_value(std::string& yaml, const std::string& name, const std::string& value) {
  const std::string key = "\n" + name + ":";
  const auto at = yaml.find(key);
  if (at == std::string::npos) return false;
  const auto from = yaml.find_first_not_of(' ', at + key.size());
  const auto end = yaml.find_first_of(" #\n", from);
  yaml.replace(at + 1, end - at - 1, name + ": " + value);
  return true;
}

// A shipped config file with some top-level values replaced, written to dir; "" if a key is
// missing.
std::string edited_config(const std::string& dir, const std::string& shipped,
                          const std::vector<std::pair<std::string, std::string>>& values) {
  std::string yaml = "\n" + read_text(sb::testing::source_path("config/" + shipped));
  for (const auto& [name, value] : values) {
    if (!set_value(yaml, name, value)) {
      std::fprintf(stderr, "bench latency: no key %s in config/%s\n", name.c_str(),
                   shipped.c_str());
      return "";
    }
  }
  const std::string path = dir + "/" + shipped;
  std::ofstream(path) << yaml.substr(1);
  return path;
}

// config/simulator.yaml with frame_rate_hz set to rate_hz.
std::string simulator_config(const std::string& dir, int rate_hz) {
  return edited_config(dir, "simulator.yaml", {{"frame_rate_hz", std::to_string(rate_hz) + ".0"}});
}

// The file source: o.file_seconds of the scenario rendered once per rate by stereoball-sim
// (raw frames, the rig's true calibration) and a camera_server config playing them at rate_hz
// in the case's encoding; "" on failure.
std::string camera_files_config(const std::string& dir, const Case& c, const Options& o) {
  static std::map<int, std::string> rendered;  // rate -> folder, kept for the whole run
  std::string& frames = rendered[c.rate_hz];
  if (frames.empty()) {
    const std::string folder = sb::testing::temp_dir() + "/frames";
    const auto [code, output] =
        sb::testing::run({sb::testing::bin("stereoball-sim"), "--config",
                          simulator_config(dir, c.rate_hz), "--scenario", o.scenario, "--duration",
                          std::to_string(o.file_seconds), "--png-dir", folder},
                         120s);
    if (code != 0) {
      std::fprintf(stderr, "bench latency: stereoball-sim failed: %s\n", output.c_str());
      return "";
    }
    frames = folder;
  }
  return edited_config(dir, "camera_server_files.yaml",
                       {{"left_glob", "\"" + frames + "/left_*.png\""},
                        {"right_glob", "\"" + frames + "/right_*.png\""},
                        {"file_encoding", "bgr8"},
                        {"frame_encoding", c.encoding},
                        {"rate_hz", std::to_string(c.rate_hz) + ".0"},
                        {"calibration_file", "\"" + frames + "/calibration.yaml\""}});
}

std::string node_yaml(const std::string& program, const std::vector<std::string>& args) {
  std::string out = "  - name: " + program + "\n    program: " + program + "\n    args: [";
  for (std::size_t i = 0; i < args.size(); ++i) out += (i ? ", \"" : "\"") + args[i] + "\"";
  return out + "]\n";
}

// A launch profile (Cyclone configuration file cyclonedds) with the simulator at the case's
// rate and encoding (plus, for one host, the vision nodes); returns its path.
std::string write_profile(const std::string& dir, const Case& c, const Options& o,
                          const std::string& cyclonedds, bool with_vision) {
  std::string yaml = "description: \"bench latency " + c.setup + " " + c.key() + "\"\n";
  yaml += "cyclonedds: \"" + cyclonedds + "\"\nnodes:\n";
  if (o.source == "files") {
    const std::string camera_config = camera_files_config(dir, c, o);
    if (camera_config.empty()) return "";
    yaml += node_yaml("camera_server", {"--config", camera_config});
  } else {
    const std::string sim_config = simulator_config(dir, c.rate_hz);
    if (sim_config.empty()) return "";
    yaml += node_yaml("simulator", {"--config", sim_config, "--scenario", o.scenario, "--loop",
                                    "--frame-encoding", c.encoding});
  }
  if (with_vision) {
    std::vector<std::string> args{"--config", o.detector_config};
    if (!o.detector_times.empty()) {
      args.push_back("--frame-times");
      args.push_back(o.detector_times + c.setup + "_" + c.key() + ".csv");
    }
    yaml += node_yaml("ball_detector", args);
    yaml += node_yaml("tracker", {"--config", sb::testing::source_path("config/tracker.yaml")});
  }
  yaml += node_yaml("motion_controller",
                    {"--config", sb::testing::source_path("config/motion_controller.yaml")});
  const std::string path = dir + "/profile.yaml";
  std::ofstream(path) << yaml;
  return path;
}

// Waits through the warm-up, measures for o.seconds, and returns [from, to) of exposures
// plus the CPU samples around it; then waits a little so the last frames' commands arrive.
struct Window {
  std::int64_t from_ns = 0, to_ns = 0;
  sd::CpuSample start, end;
  sd::ProgramSample programs_start, programs_end;
  // Each program's CPU and run-queue wait per frame period of the window.
  std::map<std::string, sd::ProgramCpu> cpu(int rate_hz) const {
    return sd::program_cpu(programs_start, programs_end,
                           static_cast<double>(to_ns - from_ns) * 1e-9 * rate_hz);
  }
};
Window measure(const Options& o, const std::vector<int>& pids) {
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(o.warmup_s * 1e3)));
  Window w;
  w.from_ns = sb::node::now_ns();
  w.start = sd::cpu_sample(pids);
  w.programs_start = sd::program_sample(pids);
  std::this_thread::sleep_for(std::chrono::milliseconds(static_cast<int>(o.seconds * 1e3)));
  w.to_ns = sb::node::now_ns();
  w.end = sd::cpu_sample(pids);
  w.programs_end = sd::program_sample(pids);
  std::this_thread::sleep_for(700ms);
  return w;
}

std::optional<Result> run_one_host(const Case& c, const Options& o, const std::string& partition) {
  const std::string dir = sb::testing::temp_dir();
  std::string config = o.one_host_cyclonedds;
  if (config.empty()) {
    config = sb::testing::source_path(o.shared_memory ? "config/cyclonedds/shm.xml"
                                                      : "config/cyclonedds/loopback.xml");
  }
  const std::string uri = "file://" + config;
  const std::string profile = write_profile(dir, c, o, config, true);
  if (profile.empty()) return std::nullopt;
  const std::vector<std::string> env{"CYCLONEDDS_URI=" + uri};
  const std::vector<std::string> common{"--domain", std::to_string(o.domain), "--partition",
                                        partition};
  std::vector<std::string> obs{sb::testing::bin("sb_netns_observer"), "--topics", "detection",
                               "track", "cmd"};
  obs.insert(obs.end(), common.begin(), common.end());
  sd::GentleProcess observer(sb::testing::Process::start(obs, env));
  if (!observer.get().wait_for_output("# observing", 20s)) {
    std::fprintf(stderr, "bench latency: observer did not start: %s\n",
                 observer.get().output().c_str());
    return std::nullopt;
  }
  std::vector<std::string> launch{sb::testing::bin("stereoball-launch"), profile, "--log",
                                  dir + "/launch.log"};
  launch.insert(launch.end(), common.begin(), common.end());
  std::optional<sd::GentleProcess> launcher(std::in_place,
                                            sb::testing::Process::start(launch, env));
  const Window w = measure(o, {launcher->get().pid(), observer.get().pid()});
  launcher.reset();  // stops the nodes before the observer
  const auto log = sd::parse_observer_log(observer.get().output());
  Result r = result_of(log, log, w.from_ns, w.to_ns, c.rate_hz, sd::core_load(w.start, w.end));
  r.cpu = w.cpu(c.rate_hz);
  r.render_lead = render_lead(read_text(dir + "/launch.log"));
  if (r.figures.end_to_end.n == 0) {
    std::fprintf(stderr, "bench latency: no command answered a track; launcher log:\n%s\n",
                 read_text(dir + "/launch.log").c_str());
    return std::nullopt;
  }
  return r;
}

std::optional<Result> run_two_hosts(const Case& c, const Options& o, const std::string& partition) {
  const std::string dir = sb::testing::temp_dir();
  const std::string lan = sb::testing::source_path("config/cyclonedds/lan.xml");
  sd::SystemOptions so;
  so.domain = o.domain;
  so.partition = partition;
  so.robot_profile = write_profile(dir, c, o, lan, false);
  so.workstation_profile = o.workstation_profile;
  if (so.robot_profile.empty()) return std::nullopt;
  so.robot_observer_topics = {"track", "cmd"};
  so.workstation_observer_topics = {"detection"};
  sd::TwoHostSystem system(so);
  if (auto e = system.start(); !e) {
    std::fprintf(stderr, "bench latency: %s\n", e.error().c_str());
    return std::nullopt;
  }
  std::vector<int> pids = system.hosts().pids(system.hosts().robot());
  const auto ws = system.hosts().pids(system.hosts().workstation());
  pids.insert(pids.end(), ws.begin(), ws.end());
  const Window w = measure(o, pids);
  Result r = result_of(system.workstation_log(), system.robot_log(), w.from_ns, w.to_ns, c.rate_hz,
                       sd::core_load(w.start, w.end));
  r.cpu = w.cpu(c.rate_hz);
  if (r.figures.end_to_end.n == 0) {
    std::fprintf(stderr, "bench latency: no command answered a track:\n%s\n",
                 system.diagnostics().c_str());
    return std::nullopt;
  }
  return r;
}

// The two-host workstation profile (deploy/workstation.yaml's nodes) with ball_detector reading
// the composed configuration; returns its path.
std::string workstation_profile(const std::string& dir, const Options& o) {
  std::string yaml = "description: \"bench latency workstation, --detector-config\"\n";
  yaml += "cyclonedds: \"" + sb::testing::source_path("config/cyclonedds/lan.xml") + "\"\n";
  yaml += "nodes:\n" + node_yaml("ball_detector", {"--config", o.detector_config});
  yaml += node_yaml("tracker", {});
  const std::string path = dir + "/workstation.yaml";
  std::ofstream(path) << yaml;
  return path;
}

// The detector configuration of every run: the shipped file, or --detector-config merged over
// it (written for the nodes to read). Prints the base and every changed key and records them
// in record; false (after one line naming the file or key) when the override is refused.
bool prepare_detector(Options& o, nlohmann::json& record) {
  const std::string base = sb::testing::source_path("config/ball_detector.yaml");
  o.detector_config = base;
  record = {{"base", base}, {"file", o.detector_override}, {"changed", nlohmann::json::array()}};
  std::printf("detector configuration: %s\n", base.c_str());
  if (o.detector_override.empty()) return true;
  sb::real_stereo::DetectorOverrides overrides;
  overrides.config_file = o.detector_override;
  const auto composed = sb::real_stereo::compose_detector_config(base, overrides);
  if (!composed) {
    std::fprintf(stderr, "bench latency: --detector-config: %s\n", composed.error().c_str());
    return false;
  }
  std::printf("  merged over it: %s (%zu changed value(s))\n", o.detector_override.c_str(),
              composed->changed_keys.size());
  for (const auto& change : composed->changed_keys) {
    std::printf("    %s\n", change.c_str());
    record["changed"].push_back(change);
  }
  const std::string dir = sb::testing::temp_dir();
  o.detector_config = dir + "/ball_detector.yaml";
  std::ofstream(o.detector_config) << composed->yaml;
  o.workstation_profile = workstation_profile(dir, o);
  return true;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

// Every number of the per-run JSON objects replaced by its median over the runs that have it.
nlohmann::json median_of(const std::vector<nlohmann::json>& runs) {
  nlohmann::json out = runs.front();
  for (auto it = out.begin(); it != out.end(); ++it) {
    if (it->is_object()) {
      std::vector<nlohmann::json> parts;
      for (const auto& r : runs) {
        if (r.contains(it.key())) parts.push_back(r.at(it.key()));
      }
      *it = median_of(parts);
    } else if (it->is_number()) {
      std::vector<double> values;
      for (const auto& r : runs) {
        if (r.contains(it.key()) && r.at(it.key()).is_number())
          values.push_back(r.at(it.key()).get<double>());
      }
      *it = median(values);
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball bench latency: exposure -> velocity command of the whole system (separate\n"
      "processes), per stage: capture -> frame received, detection, track, command, and end to\n"
      "end; raw and JPEG frames, 30 and 60 Hz; on one host (loopback Cyclone configuration)\n"
      "and with --two-hosts between two network namespaces (root, iproute2). Figures are\n"
      "printed per run and as medians over --runs."};
  Options o;
  o.domain = sb::dds::domain_from_env(0);
  app.add_option("--seconds", o.seconds, "measured seconds per case and run")
      ->check(CLI::Range(1.0, 3600.0))
      ->capture_default_str();
  app.add_option("--warmup", o.warmup_s, "seconds before measuring (start-up, calibration)")
      ->check(CLI::Range(1.0, 120.0))
      ->capture_default_str();
  app.add_option("--runs", o.runs, "runs of every case; medians are reported")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  app.add_option("--encoding", o.encodings, "frame encodings")
      ->check(CLI::IsMember({"raw", "jpeg"}))
      ->capture_default_str();
  app.add_option("--rate", o.rates_hz, "camera frame rates, Hz")
      ->check(CLI::Range(1, 120))
      ->capture_default_str();
  app.add_flag("--two-hosts", o.two_hosts, "also between two network namespaces (root)");
  app.add_flag("!--no-one-host", o.one_host, "skip the one-host setup");
  app.add_option("--scenario", o.scenario, "simulator scenario (looped)")->capture_default_str();
  app.add_option("--source", o.source,
                 "simulator (renders live, frames released at their exposure) or files "
                 "(camera_server plays --file-seconds of the scenario rendered first; stamp = "
                 "publish time); setups one_host_files / two_hosts_files")
      ->check(CLI::IsMember({"simulator", "files"}))
      ->capture_default_str();
  app.add_option("--file-seconds", o.file_seconds, "with --source files: seconds rendered")
      ->check(CLI::Range(1.0, 30.0))
      ->capture_default_str();
  app.add_option("--cyclonedds", o.one_host_cyclonedds,
                 "Cyclone configuration file for the one-host setup (default: loopback.xml)")
      ->check(CLI::ExistingFile);
  app.add_flag("--shared-memory", o.shared_memory,
               "one host: Cyclone over iceoryx shared memory (config/cyclonedds/shm.xml; starts "
               "iox-roudi with config/iceoryx/roudi.toml unless one runs); setup one_host_shm");
  app.add_option("--json", o.json_path, "also write the figures to this file");
  app.add_option("--frames-csv", o.frames_csv,
                 "write every frame's stages (warm-up included, column measured) to "
                 "PREFIX<setup>_<encoding>_<rate>hz_run<N>.csv");
  app.add_option("--detector-frame-times", o.detector_times,
                 "one host: ball_detector writes each frame's stage times (its --frame-times) to "
                 "PREFIX<setup>_<encoding>_<rate>hz.csv (the last run's)");
  app.add_option("--domain", o.domain, "DDS domain")->check(CLI::Range(0, 232));
  app.add_option("--detector-config", o.detector_override,
                 "YAML whose keys are merged over config/ball_detector.yaml for ball_detector "
                 "(any subset of it); the report and the JSON list every changed value");
  CLI11_PARSE(app, argc, argv);
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  if (!o.frames_csv.empty()) {
    // Checked before the (long) runs: a prefix in a missing folder fails at once.
    const auto dir = std::filesystem::path(o.frames_csv).parent_path();
    if (!dir.empty() && !std::filesystem::is_directory(dir)) {
      std::fprintf(stderr, "bench latency: --frames-csv %s: folder %s does not exist\n",
                   o.frames_csv.c_str(), dir.c_str());
      return 2;
    }
  }
  nlohmann::json detector_record;
  if (!prepare_detector(o, detector_record)) return 2;

  std::vector<Case> cases;
  for (const bool two : {false, true}) {
    if (two ? !o.two_hosts : !o.one_host) continue;
    for (const auto& e : o.encodings) {
      for (const int r : o.rates_hz) {
        std::string setup = two ? "two_hosts" : o.shared_memory ? "one_host_shm" : "one_host";
        if (o.source == "files") setup += "_files";
        cases.push_back({setup, e, r});
      }
    }
  }
  // RouDi for the shared-memory runs; our nodes fall back to the network without it.
  std::optional<sd::GentleProcess> roudi;
  if (o.shared_memory && o.one_host && !sb::dds::roudi_running()) {
    roudi.emplace(sb::testing::Process::start(
        {"/usr/bin/iox-roudi", "-c", sb::testing::source_path("config/iceoryx/roudi.toml")}));
    if (!roudi->get().wait_for_output("RouDi is ready", 20s)) {
      std::fprintf(stderr, "bench latency: iox-roudi (package iceoryx) did not start: %s\n",
                   roudi->get().output().c_str());
      return 1;
    }
  }
  nlohmann::json json = nlohmann::json::object();
  json["detector_config"] = detector_record;
  int failures = 0;
  for (const Case& c : cases) {
    std::vector<nlohmann::json> runs;
    for (int run = 0; run < o.runs; ++run) {
      const std::string partition = "sblatency." + std::to_string(::getpid()) + "." + c.setup +
                                    "." + c.key() + "." + std::to_string(run);
      const auto r = c.setup.rfind("two_hosts", 0) == 0 ? run_two_hosts(c, o, partition)
                                                        : run_one_host(c, o, partition);
      if (!r) {
        ++failures;
        continue;
      }
      char title[160];
      std::snprintf(title, sizeof title, "%s %s %d Hz, 640x480, %s, run %d/%d (%.0f s)",
                    c.setup.c_str(), c.encoding.c_str(), c.rate_hz, o.scenario.c_str(), run + 1,
                    o.runs, o.seconds);
      std::fputs(sd::to_text(title, r->figures, r->load).c_str(), stdout);
      std::fputs(sd::program_cpu_text(r->cpu).c_str(), stdout);
      // What the p99 frames were: lost-ball frames, or transport and scheduling.
      const sd::SlowFrames slow = sd::slowest_frames(r->frames, r->measured_from_ns, 2.0);
      std::fputs(sd::to_text(slow, 2.0).c_str(), stdout);
      const sd::Quantiles& s = r->startup.end_to_end;
      std::printf(
          "  start-up (frames exposed before the measured window: the first %.0f s after "
          "launch, not in the figures above): detection p99 %.2f max %.2f ms, end to end n=%zu "
          "p50 %.2f p99 %.2f max %.2f ms\n",
          o.warmup_s, r->startup.detection.p99, r->startup.detection.max, s.n, s.p50, s.p99, s.max);
      if (r->render_lead) print_render_lead(*r->render_lead, c.rate_hz);
      nlohmann::json j = sd::to_json(r->figures, r->load);
      if (r->render_lead) add_render_lead(*r->render_lead, j);
      j["startup"] = sd::to_json(r->startup, r->load);
      j["startup"].erase("load");
      j["cpu_per_frame"] = sd::program_cpu_json(r->cpu);
      j["slowest_2pct"] = sd::to_json(slow);
      runs.push_back(j);
      if (!o.frames_csv.empty()) {
        const std::string path =
            o.frames_csv + c.setup + "_" + c.key() + "_run" + std::to_string(run + 1) + ".csv";
        std::ofstream out(path);
        out << sd::to_csv(r->frames, r->measured_from_ns);
        if (!out.flush()) {
          // The figures of the run still count; the missing file is reported and fails the exit.
          std::fprintf(stderr, "bench latency: cannot write %s\n", path.c_str());
          ++failures;
        }
      }
    }
    if (runs.empty()) continue;
    nlohmann::json figures = median_of(runs);
    std::printf("%s %s: median of %zu run(s): end to end p50 %.2f p90 %.2f p99 %.2f max %.2f ms\n",
                c.setup.c_str(), c.key().c_str(), runs.size(),
                figures["end_to_end_ms"]["p50"].get<double>(),
                figures["end_to_end_ms"]["p90"].get<double>(),
                figures["end_to_end_ms"]["p99"].get<double>(),
                figures["end_to_end_ms"]["max"].get<double>());
    if (figures.contains("cpu_per_frame")) {
      std::map<std::string, sd::ProgramCpu> cpu;
      for (const auto& [name, v] : figures["cpu_per_frame"].items())
        cpu[name] = {v.value("cpu_ms", 0.0), v.value("runqueue_wait_ms", 0.0)};
      std::printf("%s %s: median of %zu run(s):\n%s", c.setup.c_str(), c.key().c_str(), runs.size(),
                  sd::program_cpu_text(cpu).c_str());
    }
    figures["runs"] = runs;
    json[c.setup][c.key()] = figures;
  }
  if (!o.json_path.empty()) {
    std::ofstream out(o.json_path);
    out << json.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "bench latency: cannot write %s\n", o.json_path.c_str());
      return 1;
    }
  }
  return failures == 0 ? 0 : 1;
}
