#include "two_hosts.hpp"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "process.hpp"

namespace stereoball::distributed {
namespace {

namespace fs = std::filesystem;
using std::chrono::milliseconds;
std::atomic<int> g_instance{0};

bool alive(int pid) {
  return ::kill(pid, 0) == 0;
}

}  // namespace

std::string find_ip_program() {
  for (const char* path : {"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}) {
    if (fs::exists(path)) return path;
  }
  return "";
}

Status netem_available() {
  TwoHosts probe;
  if (auto e = probe.setup(); !e) return Error{"cannot create network namespaces: " + e.error()};
  if (auto e = probe.add_netem(1, 0.0); !e) return Error{"no netem on this machine: " + e.error()};
  return {};
}

TwoHosts::TwoHosts() : ip_path_(find_ip_program()) {
  // Names and addresses unique to this process and instance, so parallel runs never meet.
  const int pid = static_cast<int>(::getpid());
  const int n = g_instance++;
  const std::string tag = std::to_string(pid) + "x" + std::to_string(n);
  const int a = 100 + (pid + n) % 100;
  const int b = (pid / 100 + n) % 250;
  const std::string net = "10." + std::to_string(a) + "." + std::to_string(b) + ".";
  robot_ = {"sbrobot" + tag, "vr" + tag, net + "1", net + "2"};
  workstation_ = {"sbws" + tag, "vw" + tag, net + "2", net + "1"};
  const std::string rogue_net =
      "172." + std::to_string(16 + (pid + n) % 16) + "." + std::to_string(b) + ".";
  rogue_ = {"sbrogue" + tag, "vq" + tag, rogue_net + "2", rogue_net + "1"};
  robot_rogue_side_ = {robot_.netns, "vp" + tag, rogue_net + "1", rogue_net + "2"};
}

TwoHosts::~TwoHosts() {
  // Processes first (so nothing keeps using the link), then the namespaces (and the veth).
  if (rogue_created_) kill_all(rogue_);
  if (robot_created_) kill_all(robot_);
  if (workstation_created_) kill_all(workstation_);
  if (rogue_created_) ip({"netns", "delete", rogue_.netns});
  if (robot_created_) ip({"netns", "delete", robot_.netns});
  if (workstation_created_) ip({"netns", "delete", workstation_.netns});
}

Status TwoHosts::ip(const std::vector<std::string>& args) const {
  std::vector<std::string> argv{ip_path_};
  argv.insert(argv.end(), args.begin(), args.end());
  auto [code, output] = testing::run(argv, milliseconds(10'000));
  if (code == 0) return {};
  std::string line;
  for (const auto& a : argv) line += (line.empty() ? "" : " ") + a;
  while (!output.empty() && output.back() == '\n') output.pop_back();
  return Error{"'" + line + "' failed (exit " + std::to_string(code) + "): " + output};
}

void TwoHosts::remove_abandoned() const {
  // Namespaces of runs that were killed before their destructor ran (e.g. a ctest timeout):
  // ours by name (sbrobot<pid>x<n>, sbws<pid>x<n>) and their creating process is gone.
  auto [code, output] = testing::run({ip_path_, "netns", "list"}, milliseconds(10'000));
  if (code != 0) return;
  std::istringstream lines(output);
  for (std::string name; lines >> name;) {
    std::string rest;
    if (name.rfind("sbrobot", 0) == 0) {
      rest = name.substr(7);
    } else if (name.rfind("sbws", 0) == 0) {
      rest = name.substr(4);
    } else if (name.rfind("sbrogue", 0) == 0) {
      rest = name.substr(7);
    } else {
      continue;
    }
    const auto x = rest.find('x');
    if (x == std::string::npos || x == 0) continue;
    const int pid = std::atoi(rest.substr(0, x).c_str());
    if (pid <= 0 || ::kill(pid, 0) == 0 || errno != ESRCH) continue;
    kill_all(Host{name, "", "", ""});
    ip({"netns", "delete", name});
  }
}

Status TwoHosts::setup() {
  if (ip_path_.empty()) return Error{"iproute2 'ip' program not found"};
  if (::geteuid() != 0) {
    return Error{"network namespaces need root (running as uid " + std::to_string(::geteuid()) +
                 ")"};
  }
  remove_abandoned();
  if (auto e = ip({"netns", "add", robot_.netns}); !e) return e;
  robot_created_ = true;
  if (auto e = ip({"netns", "add", workstation_.netns}); !e) return e;
  workstation_created_ = true;
  if (auto e = ip({"link", "add", robot_.iface, "netns", robot_.netns, "type", "veth", "peer",
                   "name", workstation_.iface, "netns", workstation_.netns});
      !e) {
    return e;
  }
  for (const Host* h : {&robot_, &workstation_}) {
    if (auto e = ip({"-n", h->netns, "addr", "add", h->address + "/24", "dev", h->iface}); !e)
      return e;
    if (auto e = ip({"-n", h->netns, "link", "set", "lo", "up"}); !e) return e;
    if (auto e = ip({"-n", h->netns, "link", "set", h->iface, "up"}); !e) return e;
  }
  return {};
}

Status TwoHosts::add_rogue() {
  if (auto e = ip({"netns", "add", rogue_.netns}); !e) return e;
  rogue_created_ = true;
  if (auto e = ip({"link", "add", rogue_.iface, "netns", rogue_.netns, "type", "veth", "peer",
                   "name", robot_rogue_side_.iface, "netns", robot_.netns});
      !e) {
    return e;
  }
  for (const Host* h : {&rogue_, &robot_rogue_side_}) {
    if (auto e = ip({"-n", h->netns, "addr", "add", h->address + "/24", "dev", h->iface}); !e)
      return e;
    if (auto e = ip({"-n", h->netns, "link", "set", "lo", "up"}); !e) return e;
    if (auto e = ip({"-n", h->netns, "link", "set", h->iface, "up"}); !e) return e;
  }
  return {};
}

std::vector<std::string> TwoHosts::command(const Host& host, const std::vector<std::string>& argv,
                                           const std::string& cyclonedds_uri) const {
  std::vector<std::string> out{ip_path_,
                               "netns",
                               "exec",
                               host.netns,
                               "/usr/bin/env",
                               "-u",
                               "CYCLONEDDS_URI",
                               "STEREOBALL_IFACE=" + host.iface,
                               "STEREOBALL_PEER=" + host.peer_address};
  if (!key_file_.empty()) out.push_back("STEREOBALL_KEY_FILE=" + key_file_);
  if (!cyclonedds_uri.empty()) out.push_back("CYCLONEDDS_URI=" + cyclonedds_uri);
  out.insert(out.end(), argv.begin(), argv.end());
  return out;
}

Status TwoHosts::set_robot_link(bool up) const {
  return ip({"-n", robot_.netns, "link", "set", robot_.iface, up ? "up" : "down"});
}

Status TwoHosts::add_netem(int delay_ms, double loss_percent) const {
  const std::string tc = fs::path(ip_path_).parent_path() / "tc";
  if (!fs::exists(tc)) return Error{"tc (iproute2) not installed"};
  std::ostringstream loss;
  loss << loss_percent << "%";
  for (const Host* h : {&robot_, &workstation_}) {
    auto [code, output] = testing::run(
        {ip_path_, "netns", "exec", h->netns, tc, "qdisc", "add", "dev", h->iface, "root", "netem",
         "delay", std::to_string(delay_ms) + "ms", "loss", loss.str()},
        milliseconds(10'000));
    if (code != 0) {
      while (!output.empty() && output.back() == '\n') output.pop_back();
      return Error{"tc qdisc add ... netem failed (exit " + std::to_string(code) + "): " + output};
    }
  }
  return {};
}

void TwoHosts::remove_netem() const {
  const std::string tc = fs::path(ip_path_).parent_path() / "tc";
  for (const Host* h : {&robot_, &workstation_}) {
    testing::run({ip_path_, "netns", "exec", h->netns, tc, "qdisc", "del", "dev", h->iface, "root"},
                 milliseconds(10'000));
  }
}

std::vector<int> TwoHosts::pids(const Host& host) const {
  auto [code, output] = testing::run({ip_path_, "netns", "pids", host.netns}, milliseconds(10'000));
  std::vector<int> out;
  if (code != 0) return out;
  std::istringstream in(output);
  for (int pid; in >> pid;) out.push_back(pid);
  return out;
}

void TwoHosts::kill_all(const Host& host) const {
  // Only processes inside this run's own namespace: ours by construction.
  auto left = pids(host);
  for (int pid : left) ::kill(pid, SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + milliseconds(4000);
  while (std::chrono::steady_clock::now() < deadline) {
    bool any = false;
    for (int pid : left) any = any || alive(pid);
    if (!any) return;
    std::this_thread::sleep_for(milliseconds(50));
  }
  for (int pid : pids(host)) ::kill(pid, SIGKILL);
}

}  // namespace stereoball::distributed
