// The chaos run itself: the nodes started in their namespaces and kept alive, memory sampled,
// each planned fault done at its time (kill, cut, flood, key rotation, e-stop, rogue), then
// everything stopped in order. The checks and the report are in chaos_judge.cpp.
#include "chaos_run.hpp"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "chaos_children.hpp"
#include "common/util/install_layout.hpp"

namespace sb = stereoball;
namespace bc = stereoball::bench_chaos;
namespace fs = std::filesystem;

namespace stereoball::bench_chaos {

void Run::note(const std::string& text) {
  std::printf("[chaos %7.1f s] %s\n", (now_ns() - start_ns_) * 1e-9, text.c_str());
  std::fflush(stdout);
}

std::vector<std::string> Run::wrap(Host host, const std::vector<std::string>& argv,
                                   const std::string& key_file, bool dds) const {
  std::vector<std::string> out;
  if (host != Host::kLocal && netns_) {
    const bool robot = host == Host::kRobot;
    out = {ns_.ip,
           "netns",
           "exec",
           robot ? ns_.robot : ns_.workstation,
           "/usr/bin/env",
           "STEREOBALL_IFACE=" + (robot ? ns_.robot_iface : ns_.ws_iface),
           "STEREOBALL_PEER=" + (robot ? ns_.ws_addr : ns_.robot_addr),
           "CYCLONEDDS_URI=file://" + sb::paths::shipped_config_path("cyclonedds/lan.xml")};
  } else {
    out = {"/usr/bin/env"};
  }
  out.push_back("STEREOBALL_KEY_FILE=" + key_file);
  out.insert(out.end(), argv.begin(), argv.end());
  if (!dds) return out;
  out.push_back("--domain");
  out.push_back(std::to_string(o_.domain));
  if (!o_.partition.empty()) {
    out.push_back("--partition");
    out.push_back(o_.partition);
  }
  return out;
}

void Run::start(Node& n) {
  n.pid = spawn(wrap(n.host, n.argv, key_file_), log_file(n.name));
  n.started_ns = now_ns();
  n.expect_exit = false;
}

void Run::poll() {
  const int64_t now = now_ns();
  for (auto& n : nodes_) {
    if (n.pid <= 0) continue;
    int status = 0;
    if (waitpid(n.pid, &status, WNOHANG) != n.pid) continue;
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (!n.expect_exit) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "%s (pid %d) exited with %d at %.1f s without being killed",
                    n.name.c_str(), n.pid, code, (now - start_ns_) * 1e-9);
      unexpected_.push_back(buf);
      note(buf);
      n.pid = -1;
      if (n.name != "recorder") {  // a new recorder would overwrite the file
        start(n);                  // keep the system running
        ++n.restarts;
      }
      continue;
    }
    n.pid = -1;
  }
  if (now < next_memory_ns_) return;
  next_memory_ns_ = now + 5 * kS;
  const int64_t warmup_ns = static_cast<int64_t>(o_.warmup_s * 1e9);
  for (const auto& n : nodes_) {
    if (n.pid <= 0 || now - n.started_ns < warmup_ns) continue;
    const Rss rss = read_rss(n.pid);
    const long kb = rss.total_kb;
    if (kb <= 0) continue;
    auto [it, fresh] = memory_.spans.try_emplace(n.pid);
    bc::MemorySpan& m = it->second;
    if (fresh) {
      m.process = n.name, m.pid = n.pid, m.first_ns = now, m.first_kb = kb;
      m.started_ns = n.started_ns;
    }
    m.last_ns = now, m.last_kb = kb;
    m.samples.push_back({now, kb});
    // Every sample, so a growth can be told from a plateau afterwards.
    if (std::FILE* csv = std::fopen((o_.out_dir + "/memory.csv").c_str(), "a")) {
      std::fprintf(csv, "%.1f,%s,%d,%ld,%ld,%ld\n", (now - start_ns_) * 1e-9, n.name.c_str(), n.pid,
                   kb, rss.anon_kb, rss.file_kb);
      std::fclose(csv);
    }
  }
}

void Run::wait_until(int64_t t_ns) {
  while (!g_stop && now_ns() < t_ns) {
    poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

int Run::tool(const std::string& name, Host host, std::vector<std::string> args,
              const std::string& key_file, int64_t timeout_ns) {
  args.insert(args.begin(), name.front() == '/' ? name : bin(name));
  const bool dds = name != "stereoball-keys";
  const pid_t pid = spawn(wrap(host, args, key_file, dds), log_file("tools"));
  const int64_t deadline = now_ns() + timeout_ns;
  for (;;) {
    int status = 0;
    if (waitpid(pid, &status, WNOHANG) == pid) {
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      if (code != 0) {
        ++tool_failures_;
        note(name + " " + (args.size() > 1 ? args[1] : "") + " exited with " +
             std::to_string(code) + " (see tools.log)");
      }
      return code;
    }
    if (now_ns() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      ++tool_failures_;
      note(name + " did not finish in time");
      return -1;
    }
    poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// kKillNode: SIGKILL or SIGTERM, the node restarted after f's duration (SIGKILL after a
// grace if it is still shutting down).
void Run::kill_and_restart(const bc::Fault& f, const std::string& seconds) {
  Node& n = nodes_[static_cast<size_t>(f.node) % 4];
  if (n.pid <= 0) return;
  note("kill " + n.name + " (pid " + std::to_string(n.pid) + ", " +
       (f.sigkill ? "SIGKILL" : "SIGTERM") + "), restart after " + seconds + " s");
  n.expect_exit = true;
  kill(n.pid, f.sigkill ? SIGKILL : SIGTERM);
  wait_until(now_ns() + f.duration_ns);
  // A SIGTERM'd node may still be shutting down: give it the rest of a grace period.
  const int64_t grace_end = now_ns() + 5 * kS;
  while (n.pid > 0 && now_ns() < grace_end) wait_until(now_ns() + 100'000'000);
  if (n.pid > 0) {
    kill(n.pid, SIGKILL);
    wait_until(now_ns() + 200'000'000);
  }
  if (n.pid <= 0) {
    start(n);
    ++n.restarts;
  }
}

// kEstop: engaged, held for f's duration, then released for certain.
void Run::hold_estop(const bc::Fault& f, const std::string& seconds) {
  note("engage the e-stop for " + seconds + " s");
  const int code = tool("stereoball-estop", Host::kRobot,
                        {"engage", "--reason", "chaos", "--wait", "5"}, key_file_, 30 * kS);
  const int64_t begin = now_ns();
  wait_until(begin + f.duration_ns);
  const int64_t end = now_ns();
  // Held from the moment engage returned (published and acknowledged) to the release.
  if (code == 0) timeline_.estop.push_back({begin, end});
  // Released for certain, even when the first attempt fails.
  for (int attempt = 0; attempt < 3; ++attempt) {
    if (tool("stereoball-estop", Host::kRobot,
             {"release", "--confirm", "--reason", "chaos", "--wait", "5"}, key_file_, 30 * kS) == 0)
      break;
  }
}

void Run::do_fault(const bc::Fault& f) {
  ++fault_counts_[std::string(bc::to_string(f.kind))];
  const double d = f.duration_ns * 1e-9;
  const std::string seconds = std::to_string(d);
  switch (f.kind) {
    case bc::FaultKind::kKillNode:
      kill_and_restart(f, seconds);
      return;
    case bc::FaultKind::kCutLink: {
      note("cut the link for " + seconds + " s");
      const int64_t begin = now_ns();
      if (!ns_.set_link(false)) note("could not take the link down");
      wait_until(begin + f.duration_ns);
      if (!ns_.set_link(true)) note("could not bring the link up");
      timeline_.link_cuts.push_back({begin, now_ns()});
      return;
    }
    case bc::FaultKind::kFloodFrames: {
      note("flood stereo/frame with garbage for " + seconds + " s");
      const int64_t begin = now_ns();
      tool_child("flood", d);
      timeline_.floods.push_back({begin, now_ns()});
      return;
    }
    case bc::FaultKind::kRotateKey:
      note("rotate the deployment key");
      tool("stereoball-keys", Host::kLocal, {"rotate", "--file", key_file_, "--grace", "120"},
           key_file_, 20 * kS);
      return;
    case bc::FaultKind::kEstop:
      hold_estop(f, seconds);
      return;
    case bc::FaultKind::kRogueCommands: {
      note("commands signed with an unknown key for " + seconds + " s");
      const int64_t begin = now_ns();
      tool_child("rogue", d);
      timeline_.rogue.push_back({begin, now_ns()});
      return;
    }
  }
}

void Run::tool_child(const std::string& mode, double seconds) {
  const std::string key = mode == "rogue" ? rogue_key_ : key_file_;
  tool(self_, Host::kRobot,
       {"--child", mode, "--child-seconds", std::to_string(seconds), "--seed",
        std::to_string(o_.seed + static_cast<uint64_t>(++child_runs_))},
       key, static_cast<int64_t>(seconds * 1e9) + 30 * kS);
}

void Run::stop_all() {
  // Nodes first (SIGTERM, then SIGKILL after a grace), the recorder last (SIGINT: a complete
  // file).
  next_memory_ns_ = 0;
  poll();  // the last memory sample
  for (size_t i = 0; i + 1 < nodes_.size(); ++i) {
    nodes_[i].expect_exit = true;
    if (nodes_[i].pid > 0) kill(nodes_[i].pid, SIGTERM);
  }
  auto wait_nodes = [&](size_t from, size_t to, int64_t grace_ns) {
    const int64_t deadline = now_ns() + grace_ns;
    for (;;) {
      bool any = false;
      for (size_t i = from; i < to; ++i) {
        auto& n = nodes_[i];
        if (n.pid <= 0) continue;
        int status = 0;
        if (waitpid(n.pid, &status, WNOHANG) == n.pid) {
          n.pid = -1;
        } else {
          any = true;
        }
      }
      if (!any) return;
      if (now_ns() > deadline) {
        for (size_t i = from; i < to; ++i) {
          if (nodes_[i].pid > 0) {
            kill(nodes_[i].pid, SIGKILL);
            waitpid(nodes_[i].pid, nullptr, 0);
            nodes_[i].pid = -1;
          }
        }
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  };
  wait_nodes(0, nodes_.size() - 1, 8 * kS);
  Node& recorder = nodes_.back();
  recorder.expect_exit = true;
  if (recorder.pid > 0) kill(recorder.pid, SIGINT);
  wait_nodes(nodes_.size() - 1, nodes_.size(), 30 * kS);
}

int Run::main() {
  if (const int code = prepare_files(); code != 0) return code;
  const std::string netns_note = make_namespaces();
  std::printf("stereoball bench chaos: %s; files in %s\n", netns_note.c_str(), o_.out_dir.c_str());
  if (const int code = start_nodes(); code != 0) return code;
  const size_t planned = run_faults();
  note("stopping");
  stop_all();
  return judge(netns_note, planned);
}

int Run::prepare_files() {
  self_ = fs::read_symlink("/proc/self/exe").string();
  if (o_.bin_dir.empty()) o_.bin_dir = fs::path(self_).parent_path().string();
  if (o_.out_dir.empty())
    o_.out_dir = (fs::temp_directory_path() / ("sb_chaos_" + std::to_string(getpid()))).string();
  std::error_code ec;
  fs::create_directories(o_.out_dir + "/keys", ec);
  if (ec) {
    std::fprintf(stderr, "stereoball bench chaos: cannot create %s: %s\n", o_.out_dir.c_str(),
                 ec.message().c_str());
    return 2;
  }
  chmod((o_.out_dir + "/keys").c_str(), 0700);
  key_file_ = o_.out_dir + "/keys/deployment.key";
  rogue_key_ = o_.out_dir + "/keys/rogue.key";
  base_log_ = o_.out_dir + "/base.log";
  mcap_ = o_.out_dir + "/chaos.mcap";
  fs::remove(base_log_, ec);
  fs::remove(mcap_, ec);
  fs::remove(o_.out_dir + "/memory.csv", ec);
  if (std::FILE* csv = std::fopen((o_.out_dir + "/memory.csv").c_str(), "w")) {
    std::fputs("t_s,process,pid,rss_kb,anon_kb,file_kb\n", csv);
    std::fclose(csv);
  }
  for (const auto& k : {key_file_, rogue_key_}) {
    if (run_command({bin("stereoball-keys"), "init", "--force", "--file", k}, log_file("tools"),
                    20 * kS) != 0) {
      std::fprintf(stderr, "stereoball bench chaos: stereoball-keys init failed (see %s)\n",
                   log_file("tools").c_str());
      return 2;
    }
  }
  return 0;
}

std::string Run::make_namespaces() {
  std::string netns_note;
  if (o_.no_netns) {
    netns_note = "one host (--no-netns): the link fault is skipped";
  } else if (auto e = ns_.make(); !e) {
    netns_note =
        "one host: network namespaces unavailable (" + e.error() + "): the link fault is skipped";
  } else {
    netns_ = true;
    netns_note =
        "two namespaces (robot: simulator, recorder; workstation: ball_detector, "
        "tracker, motion_controller)";
  }
  return netns_note;
}

int Run::start_nodes() {
  nodes_ = {
      {"simulator",
       {bin("simulator"), "--scenario", o_.scenario, "--loop", "--base-log", base_log_},
       Host::kRobot},
      {"ball_detector", {bin("ball_detector")}, Host::kWorkstation},
      {"tracker", {bin("tracker")}, Host::kWorkstation},
      {"motion_controller", {bin("motion_controller")}, Host::kWorkstation},
      {"recorder",
       {bin("stereoball-record"), "-o", mcap_, "--no-derived", "-q", "sim/ground_truth",
        "cmd/velocity", "ball/track", "ball/detection", "cmd/estop"},
       Host::kRobot},
  };
  for (const auto& n : nodes_) {
    if (!fs::exists(n.argv.front())) {
      std::fprintf(stderr, "stereoball bench chaos: %s is not built\n", n.argv.front().c_str());
      return 2;
    }
  }
  start(nodes_.back());  // the recorder first: it must see every sample
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  for (size_t i = 0; i + 1 < nodes_.size(); ++i) start(nodes_[i]);
  return 0;
}

size_t Run::run_faults() {
  const auto total_ns = static_cast<int64_t>(o_.minutes * 60e9);
  const auto warmup_ns = static_cast<int64_t>(o_.warmup_s * 1e9);
  bc::PlanParams plan;
  plan.span_ns = std::max<int64_t>(0, total_ns - warmup_ns - 10 * kS);
  plan.mean_gap_ns = static_cast<int64_t>(o_.mean_gap_s * 1e9);
  plan.link = netns_;
  auto faults = bc::plan_faults(plan, o_.seed);
  if (o_.one_round) faults = bc::first_round(faults);
  note("nodes started; " + std::to_string(faults.size()) + " faults planned");
  const int64_t faults_start = start_ns_ + warmup_ns;
  wait_until(faults_start);
  for (const auto& f : faults) {
    if (g_stop) break;
    wait_until(std::max(faults_start + f.at_ns, now_ns()));
    do_fault(f);
  }
  // A one-round run ends once the last fault has been over for the tail (the nodes settle).
  wait_until(o_.one_round ? std::min(start_ns_ + total_ns, now_ns() + 10 * kS)
                          : start_ns_ + total_ns);
  return faults.size();
}

}  // namespace stereoball::bench_chaos
