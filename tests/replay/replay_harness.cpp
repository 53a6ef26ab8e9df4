#include "replay_harness.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <thread>

namespace stereoball::replay {
namespace {

namespace st = stereoball::testing;
using json = nlohmann::json;
using namespace std::chrono_literals;

std::string config(const std::string& file) {
  const char* dir = std::getenv("SB_REPLAY_CONFIG_DIR");
  return (dir ? std::string(dir) : st::source_path("config")) + "/" + file;
}

std::vector<std::string> dds_flags(const std::string& partition) {
  return {"--domain", std::to_string(st::test_domain()), "--partition", partition};
}

json load_reference(const std::string& name) {
  std::ifstream in(reference_path(name));
  if (!in) return json();
  return json::parse(in, nullptr, false);
}

void save_reference(const std::string& name, const json& j) {
  std::ofstream out(reference_path(name));
  out << j.dump(1) << "\n";
  std::printf("regenerated %s\n", reference_path(name).c_str());
}

// Numbers, or arrays of numbers of the same length, equal within tol.
bool near(const json& a, const json& b, double tol) {
  if (a.is_number() && b.is_number()) return std::abs(a.get<double>() - b.get<double>()) <= tol;
  if (!a.is_array() || !b.is_array() || a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (std::abs(a[i].get<double>() - b[i].get<double>()) > tol) return false;
  return true;
}

}  // namespace

std::vector<std::string> node_argv(const std::string& name, const std::string& config_file,
                                   const std::string& partition) {
  std::vector<std::string> argv = {st::bin(name), "--config", config(config_file)};
  for (auto& f : dds_flags(partition)) argv.push_back(f);
  return argv;
}

std::vector<std::string> play_argv(const std::string& recording,
                                   const std::vector<std::string>& topics,
                                   const std::string& partition) {
  std::vector<std::string> argv = {
      st::bin("stereoball-play"), recording, "--rate", kPlayRate, "--wait", "2", "--topics"};
  argv.insert(argv.end(), topics.begin(), topics.end());
  for (auto& f : dds_flags(partition)) argv.push_back(f);
  return argv;
}

void pump(st::Process& play, const std::function<void()>& poll, std::chrono::milliseconds linger) {
  const auto deadline = std::chrono::steady_clock::now() + 60s;
  while (play.running() && std::chrono::steady_clock::now() < deadline) {
    poll();
    std::this_thread::sleep_for(5ms);
  }
  const auto end = std::chrono::steady_clock::now() + linger;
  while (std::chrono::steady_clock::now() < end) {
    poll();
    std::this_thread::sleep_for(5ms);
  }
}

topics::QosSpec keep_all(topics::QosSpec qos) {
  qos.history_depth = 1000;
  qos.deadline_ns = 0;
  return qos;
}

bool regenerate_references() {
  const char* v = std::getenv("SB_REGENERATE_REFERENCES");
  return v != nullptr && std::string(v) == "1";
}

std::string reference_path(const std::string& name) {
  return st::source_path("tests/replay/reference/" + name);
}

json reference(const std::string& name, const json& actual) {
  if (regenerate_references()) save_reference(name, actual);
  return load_reference(name);
}

std::vector<std::string> compare(const json& actual, const json& reference,
                                 const std::vector<std::string>& exact,
                                 const std::vector<std::pair<std::string, double>>& toleranced,
                                 std::size_t& common) {
  std::map<std::uint64_t, json> ref;
  for (const auto& f : reference) ref[f["seq"].get<std::uint64_t>()] = f;
  std::vector<std::string> diffs;
  common = 0;
  for (const auto& f : actual) {
    const auto seq = f["seq"].get<std::uint64_t>();
    const auto it = ref.find(seq);
    if (it == ref.end()) {
      diffs.push_back("seq " + std::to_string(seq) + " not in the reference");
      continue;
    }
    ++common;
    const json& r = it->second;
    for (const auto& k : exact)
      if (f[k] != r[k])
        diffs.push_back("seq " + std::to_string(seq) + " " + k + ": " + f[k].dump() +
                        " vs reference " + r[k].dump());
    for (const auto& [k, tol] : toleranced)
      if (!near(f[k], r[k], tol))
        diffs.push_back("seq " + std::to_string(seq) + " " + k + ": " + f[k].dump() +
                        " vs reference " + r[k].dump() + " (tolerance " + std::to_string(tol) +
                        ")");
  }
  return diffs;
}

std::string first_diffs(const std::vector<std::string>& diffs, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < std::min(n, diffs.size()); ++i) s += diffs[i] + "\n";
  return s;
}

}  // namespace stereoball::replay
