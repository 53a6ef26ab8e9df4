#include "two_host_system.hpp"

#include <signal.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>

namespace stereoball::distributed {
namespace {

using std::chrono::milliseconds;

std::string tail_of_file(const std::string& path, size_t max_chars) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  std::string text = ss.str();
  return text.size() > max_chars ? "..." + text.substr(text.size() - max_chars) : text;
}

std::string lan_config_uri() {
  return "file://" + testing::source_path("config/cyclonedds/lan.xml");
}

}  // namespace

GentleProcess::~GentleProcess() {
  if (process_.running()) {
    process_.signal(SIGTERM);
    process_.wait_for_exit(milliseconds(6000));
  }
}

TwoHostSystem::TwoHostSystem(SystemOptions options) : options_(std::move(options)) {}

TwoHostSystem::~TwoHostSystem() {
  // Launchers last-in first-out, then the observers; hosts_ removes anything left.
  while (!processes_.empty()) processes_.pop_back();
}

Status TwoHostSystem::start() {
  if (auto e = hosts_.setup(); !e) {
    unavailable_ = true;
    return Error{"cannot create two network namespaces joined by veth: " + e.error()};
  }
  if (options_.rogue_host) {
    if (auto e = hosts_.add_rogue(); !e) {
      unavailable_ = true;
      return Error{"cannot create the third (rogue) namespace: " + e.error()};
    }
  }
  dir_ = testing::temp_dir();
  // Across hosts every node needs the deployment key (keyless processes stay on loopback).
  key_file_ = dir_ + "/deployment.key";
  auto [code, output] = testing::run({testing::bin("stereoball-keys"), "init", "--file", key_file_},
                                     milliseconds(20'000));
  if (code != 0) return Error{"stereoball-keys init failed: " + output};
  hosts_.set_key_file(key_file_);
  const std::string domain = std::to_string(options_.domain);
  auto observer = [&](const Host& host, const std::vector<std::string>& topics) {
    std::vector<std::string> argv{testing::bin("sb_netns_observer"),
                                  "--domain",
                                  domain,
                                  "--partition",
                                  options_.partition,
                                  "--topics"};
    argv.insert(argv.end(), topics.begin(), topics.end());
    processes_.push_back(std::make_unique<GentleProcess>(
        testing::Process::start(hosts_.command(host, argv, lan_config_uri()))));
    return processes_.back().get();
  };
  robot_observer_ = observer(hosts_.robot(), options_.robot_observer_topics);
  if (!options_.workstation_observer_topics.empty()) {
    workstation_observer_ = observer(hosts_.workstation(), options_.workstation_observer_topics);
  }
  auto launch = [&](const Host& host, const std::string& profile, const std::string& log) {
    std::vector<std::string> argv{testing::bin("stereoball-launch"),
                                  profile,
                                  "--domain",
                                  domain,
                                  "--partition",
                                  options_.partition,
                                  "--log",
                                  dir_ + "/" + log};
    processes_.push_back(
        std::make_unique<GentleProcess>(testing::Process::start(hosts_.command(host, argv))));
  };
  for (GentleProcess* o : {robot_observer_, workstation_observer_}) {
    if (o && !o->get().wait_for_output("# observing", milliseconds(10'000))) {
      return Error{"observer did not start in its namespace: " + o->get().output()};
    }
  }
  launch(hosts_.workstation(), options_.workstation_profile, "workstation.log");
  launch(hosts_.robot(), options_.robot_profile, "robot.log");
  return {};
}

std::pair<int, std::string> TwoHostSystem::run_tool(const Host& host,
                                                    const std::vector<std::string>& argv,
                                                    const std::string& key_file) const {
  std::vector<std::string> full = hosts_.command(host, {"/usr/bin/env"}, lan_config_uri());
  full.push_back("STEREOBALL_KEY_FILE=" + key_file);  // the last assignment wins
  full.insert(full.end(), argv.begin(), argv.end());
  return testing::run(full, milliseconds(30'000));
}

testing::Process& TwoHostSystem::start_in(const Host& host, const std::vector<std::string>& argv,
                                          const std::string& key_file) {
  std::vector<std::string> full = hosts_.command(host, {"/usr/bin/env"}, lan_config_uri());
  full.push_back("STEREOBALL_KEY_FILE=" + key_file);
  full.insert(full.end(), argv.begin(), argv.end());
  processes_.push_back(std::make_unique<GentleProcess>(testing::Process::start(full)));
  return processes_.back()->get();
}

ObserverLog TwoHostSystem::robot_log() const {
  return robot_observer_ ? parse_observer_log(robot_observer_->get().output()) : ObserverLog{};
}

ObserverLog TwoHostSystem::workstation_log() const {
  return workstation_observer_ ? parse_observer_log(workstation_observer_->get().output())
                               : ObserverLog{};
}

std::string TwoHostSystem::diagnostics() const {
  if (dir_.empty()) return "";
  return "--- robot namespace (" + hosts_.robot().netns + ") nodes:\n" +
         tail_of_file(dir_ + "/robot.log", 3000) + "\n--- workstation namespace (" +
         hosts_.workstation().netns + ") nodes:\n" + tail_of_file(dir_ + "/workstation.log", 3000);
}

std::vector<std::string> TwoHostSystem::programs(const Host& host) const {
  std::vector<std::string> names;
  for (int pid : hosts_.pids(host)) {
    std::ifstream comm("/proc/" + std::to_string(pid) + "/comm");
    std::string name;
    if (std::getline(comm, name)) names.push_back(name);
  }
  return names;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double pos = p / 100.0 * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<size_t>(pos);
  const size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (values[hi] - values[lo]) * (pos - static_cast<double>(lo));
}

}  // namespace stereoball::distributed
