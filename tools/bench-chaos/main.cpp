// stereoball bench chaos --minutes N [--seed S] [--json FILE]: the whole system on the simulator
// (simulator, ball_detector, tracker, motion_controller as processes, the robot side and the
// workstation side in two network namespaces when `ip netns` works here) follows the ball while
// seeded faults hit it: nodes killed and restarted, the link cut, garbage on stereo/frame, the
// deployment key rotated, the e-stop engaged, commands signed with an unknown key. Afterwards
// the simulator's base log, the run's timeline, `stereoball record`'s file and /proc memory
// samples are judged by chaos_checks (exit 1 when a check fails).

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "chaos_checks.hpp"
#include "chaos_plan.hpp"
#include "common/dds/writer.hpp"
#include "common/node/node_runner.hpp"
#include "common/util/install_layout.hpp"
#include "common/util/json_text.hpp"
#include "recorder/core/reader.hpp"
#include "recorder/io/file_io.hpp"
#include "stereoball/topics.hpp"

namespace sb = stereoball;
namespace bc = stereoball::bench_chaos;
namespace fs = std::filesystem;

namespace {

constexpr int64_t kS = 1'000'000'000;
// The rogue's commands carry seq from here on, so the recording tells them apart.
constexpr uint64_t kRogueSeqBase = uint64_t{1} << 62;

int64_t now_ns() {
  return sb::node::now_ns();
}

struct Options {
  double minutes = 1.0;
  uint64_t seed = 1;
  std::string json_path;
  std::string out_dir;
  std::string bin_dir;
  std::string scenario = "ball_kicked_past_right";
  double mean_gap_s = 8.0;
  double warmup_s = 10.0;
  bool one_round = false;  // each fault kind once, then stop kTail after the last
  bool no_netns = false;
  double memory_min_span_s = 300.0;
  double memory_settle_s = 120.0;
  double memory_max_growth_percent = 5.0;
  int domain = 0;
  std::string partition;
  // Child modes (the run starts itself for these).
  std::string child;
  double child_seconds = 0;
};

// ---------------------------------------------------------------------------------------------
// Child modes: a flood of garbage frames, or a rogue issuing commands with an unknown key.

volatile sig_atomic_t g_stop = 0;
void on_signal(int) {
  g_stop = 1;
}

int run_flood(const Options& o) {
  // With the deployment's key (from STEREOBALL_KEY_FILE) only to use the LAN: stereo/frame is
  // not authenticated, so anything on the network can publish frames like these.
  sb::dds::DomainParticipant participant({o.domain, o.partition});
  sb::dds::DataWriter<stereoball_msg_StereoFrame> writer(participant, sb::topics::kStereoFrame);
  std::mt19937_64 rng(o.seed);
  const char* encodings[] = {"bgr8", "jpeg", "png", "mono8", "yuyv", "", "bgr8\x01x"};
  std::vector<uint8_t> left, right;
  const int64_t until = now_ns() + static_cast<int64_t>(o.child_seconds * 1e9);
  uint64_t sent = 0;
  while (!g_stop && now_ns() < until) {
    // Sizes that lie about the data, data that is not an image, stamps anywhere.
    left.resize(rng() % 70'000);
    right.resize(rng() % 4 == 0 ? left.size() : rng() % 70'000);
    for (auto& b : left) b = static_cast<uint8_t>(rng());
    for (auto& b : right) b = static_cast<uint8_t>(rng());
    if (rng() % 3 == 0 && left.size() > 4) {  // a JPEG or PNG signature in front of garbage
      left[0] = 0xff, left[1] = 0xd8, left[2] = 0xff, left[3] = 0xe0;
    }
    stereoball_msg_StereoFrame f{};
    f.seq = rng();
    f.stamp_ns = rng() % 2 ? now_ns() : static_cast<int64_t>(rng());
    std::string source = "chaos-flood";
    f.source = source.data();
    f.encoding = const_cast<char*>(encodings[rng() % std::size(encodings)]);
    f.rectified = rng() % 2;
    for (auto* eye : {&f.left, &f.right}) {
      eye->capture_stamp_ns = rng() % 2 ? f.stamp_ns : static_cast<int64_t>(rng());
      eye->width_px = rng() % 4 ? 640 : static_cast<uint32_t>(rng() % 100'000);
      eye->height_px = rng() % 4 ? 480 : static_cast<uint32_t>(rng() % 100'000);
      eye->step_bytes = rng() % 2 ? eye->width_px * 3 : static_cast<uint32_t>(rng());
    }
    f.left.data._buffer = left.data();
    f.left.data._length = f.left.data._maximum = static_cast<uint32_t>(left.size());
    f.right.data._buffer = right.data();
    f.right.data._length = f.right.data._maximum = static_cast<uint32_t>(right.size());
    writer.write(f, now_ns());
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::printf("flood: %llu garbage frames sent\n", static_cast<unsigned long long>(sent));
  return 0;
}

int run_rogue(const Options& o) {
  // The key file comes from STEREOBALL_KEY_FILE: a key the deployment does not know.
  sb::dds::DomainParticipant participant({o.domain, o.partition});
  sb::dds::DataWriter<stereoball_msg_VelocityCommand> writer(participant,
                                                             sb::topics::kVelocityCommand);
  const int64_t until = now_ns() + static_cast<int64_t>(o.child_seconds * 1e9);
  uint64_t sent = 0;
  std::string source = "chaos-rogue";
  while (!g_stop && now_ns() < until) {
    stereoball_msg_VelocityCommand c{};
    c.seq = kRogueSeqBase + sent;
    c.stamp_ns = now_ns();
    c.linear_mps = 0.9;
    c.angular_radps = -1.7;
    c.source = source.data();
    writer.write(c);
    ++sent;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::printf("rogue: %llu commands sent\n", static_cast<unsigned long long>(sent));
  return 0;
}

// ---------------------------------------------------------------------------------------------
// Processes.

std::string ip_program() {
  for (const char* p : {"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}) {
    if (fs::exists(p)) return p;
  }
  return "";
}

// Runs argv to completion with a deadline; exit code (or -1 on timeout / failure to start).
int run_command(const std::vector<std::string>& argv, const std::string& log_path,
                int64_t timeout_ns);

pid_t spawn(const std::vector<std::string>& argv, const std::string& log_path) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  setpgid(0, 0);
  const int fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd >= 0) {
    dup2(fd, STDOUT_FILENO);
    dup2(fd, STDERR_FILENO);
    close(fd);
  }
  std::vector<char*> args;
  std::vector<std::string> copy = argv;
  for (auto& a : copy) args.push_back(a.data());
  args.push_back(nullptr);
  execv(args[0], args.data());
  std::perror("exec");
  _exit(127);
}

int run_command(const std::vector<std::string>& argv, const std::string& log_path,
                int64_t timeout_ns) {
  const pid_t pid = spawn(argv, log_path);
  if (pid < 0) return -1;
  const int64_t deadline = now_ns() + timeout_ns;
  for (;;) {
    int status = 0;
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid) return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (now_ns() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// Resident memory of a process from /proc/PID/status, kB: all of it (VmRSS), and its parts:
// anonymous (heap, stacks: what a leak grows) and file-backed (code and data of the program
// and its libraries, mapped in as it first runs them).
struct Rss {
  long total_kb = -1, anon_kb = -1, file_kb = -1;
};

Rss read_rss(pid_t pid) {
  Rss r;
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) r.total_kb = std::atol(line.c_str() + 6);
    if (line.rfind("RssAnon:", 0) == 0) r.anon_kb = std::atol(line.c_str() + 8);
    if (line.rfind("RssFile:", 0) == 0) r.file_kb = std::atol(line.c_str() + 8);
  }
  return r;
}

// The two "hosts": robot (simulator, recorder, e-stop, flood, rogue) and workstation
// (ball_detector, tracker, motion_controller), joined by a veth link the run can cut.
struct Namespaces {
  std::string ip;
  std::string robot, workstation, robot_iface, ws_iface, robot_addr, ws_addr;
  bool created = false;

  sb::Status make() {
    ip = ip_program();
    if (ip.empty()) return sb::Error{"iproute2 'ip' not found"};
    if (geteuid() != 0) return sb::Error{"network namespaces need root"};
    const std::string tag = std::to_string(getpid());
    robot = "sbchaosr" + tag, workstation = "sbchaosw" + tag;
    robot_iface = "vcr" + tag, ws_iface = "vcw" + tag;
    const std::string net = "10.251." + std::to_string(getpid() % 250) + ".";
    robot_addr = net + "1", ws_addr = net + "2";
    const std::string log = "/dev/null";
    auto ipc = [&](std::vector<std::string> args) -> sb::Status {
      args.insert(args.begin(), ip);
      const int code = run_command(args, log, 10 * kS);
      if (code != 0) {
        std::string line;
        for (const auto& a : args) line += a + " ";
        return sb::Error{"'" + line + "' failed (exit " + std::to_string(code) + ")"};
      }
      return {};
    };
    if (auto e = ipc({"netns", "add", robot}); !e) return e;
    created = true;
    if (auto e = ipc({"netns", "add", workstation}); !e) return e;
    if (auto e = ipc({"link", "add", robot_iface, "netns", robot, "type", "veth", "peer", "name",
                      ws_iface, "netns", workstation});
        !e)
      return e;
    for (auto [ns, iface, addr] :
         {std::tuple{robot, robot_iface, robot_addr}, std::tuple{workstation, ws_iface, ws_addr}}) {
      if (auto e = ipc({"-n", ns, "addr", "add", addr + "/24", "dev", iface}); !e) return e;
      if (auto e = ipc({"-n", ns, "link", "set", "lo", "up"}); !e) return e;
      if (auto e = ipc({"-n", ns, "link", "set", iface, "up"}); !e) return e;
    }
    return {};
  }
  bool set_link(bool up) const {
    return run_command({ip, "-n", robot, "link", "set", robot_iface, up ? "up" : "down"},
                       "/dev/null", 10 * kS) == 0;
  }
  ~Namespaces() {
    if (!created) return;
    for (const auto& ns : {robot, workstation}) {
      run_command({ip, "netns", "delete", ns}, "/dev/null", 10 * kS);
    }
  }
};

enum class Host { kLocal, kRobot, kWorkstation };

struct Node {
  std::string name;
  std::vector<std::string> argv;
  Host host = Host::kLocal;
  pid_t pid = -1;
  int64_t started_ns = 0;
  bool expect_exit = false;
  int restarts = 0;
};

struct MemoryTrack {
  std::map<pid_t, bc::MemorySpan> spans;  // per process instance
};

class Run {
 public:
  Run(Options o) : o_(std::move(o)) {}
  int main();

 private:
  // argv run on host (in its namespace, with its DDS configuration and key file); dds: the
  // program takes --domain/--partition.
  std::vector<std::string> wrap(Host host, const std::vector<std::string>& argv,
                                const std::string& key_file, bool dds = true) const;
  void start(Node& n);
  void poll();  // reap exits (restart the unexpected ones), sample memory
  void wait_until(int64_t t_ns);
  // Runs a program to completion (name in the bin dir, or a path), counting failures.
  int tool(const std::string& name, Host host, std::vector<std::string> args,
           const std::string& key_file, int64_t timeout_ns);
  // This program in a child mode (flood or rogue) for seconds, in the robot namespace.
  void tool_child(const std::string& mode, double seconds);
  void stop_all();
  int report(const std::vector<bc::CheckResult>& checks, const std::vector<bc::TopicLoss>& losses,
             const std::map<std::string, uint64_t>& recorded, const std::string& netns_note,
             size_t planned);
  void do_fault(const bc::Fault& f);
  bc::MemoryRule memory_rule() const {
    bc::MemoryRule r;
    r.settle_ns = static_cast<int64_t>(o_.memory_settle_s * 1e9);
    r.min_span_ns = static_cast<int64_t>(o_.memory_min_span_s * 1e9);
    r.max_growth_percent = o_.memory_max_growth_percent;
    return r;
  }
  std::string bin(const std::string& name) const { return o_.bin_dir + "/" + name; }
  std::string log_file(const std::string& name) const { return o_.out_dir + "/" + name + ".log"; }
  void note(const std::string& text);

  Options o_;
  Namespaces ns_;
  bool netns_ = false;
  std::string key_file_, rogue_key_, base_log_, mcap_;
  std::vector<Node> nodes_;  // 0..3 may be killed; the recorder is last
  std::vector<std::string> unexpected_;
  MemoryTrack memory_;
  int64_t next_memory_ns_ = 0;
  bc::Timeline timeline_;
  std::map<std::string, int> fault_counts_;
  int tool_failures_ = 0;
  int child_runs_ = 0;
  std::string self_;
  int64_t start_ns_ = now_ns();
};

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

void Run::do_fault(const bc::Fault& f) {
  ++fault_counts_[std::string(bc::to_string(f.kind))];
  const double d = f.duration_ns * 1e-9;
  const std::string seconds = std::to_string(d);
  switch (f.kind) {
    case bc::FaultKind::kKillNode: {
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
      return;
    }
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
    case bc::FaultKind::kEstop: {
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
                 {"release", "--confirm", "--reason", "chaos", "--wait", "5"}, key_file_,
                 30 * kS) == 0)
          break;
      }
      return;
    }
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

using sb::util::json_escape;

int Run::report(const std::vector<bc::CheckResult>& checks,
                const std::vector<bc::TopicLoss>& losses,
                const std::map<std::string, uint64_t>& recorded, const std::string& netns_note,
                size_t planned) {
  bool passed = true;
  for (const auto& c : checks) passed = passed && c.passed;
  std::string command = "stereoball bench chaos --minutes " + std::to_string(o_.minutes) +
                        " --seed " + std::to_string(o_.seed) + (o_.one_round ? " --one-round" : "");
  std::printf("\n== stereoball bench chaos: %s ==\n", passed ? "PASS" : "FAIL");
  std::printf("seed %llu, %.1f min, %s\n", static_cast<unsigned long long>(o_.seed), o_.minutes,
              netns_note.c_str());
  std::printf("faults (%zu):", planned);
  for (const auto& [kind, n] : fault_counts_) std::printf(" %s %d", kind.c_str(), n);
  std::printf("; tool failures %d\n", tool_failures_);
  for (const auto& n : nodes_) std::printf("  %-18s restarts %d\n", n.name.c_str(), n.restarts);
  std::printf("\nchecks:\n");
  for (const auto& c : checks) {
    std::printf("  %-4s %-45s %s\n", c.passed ? (c.applicable ? "ok" : "n/a") : "FAIL",
                c.name.c_str(), c.detail.c_str());
  }
  const bc::MemoryRule rule = memory_rule();
  std::printf(
      "\nmemory (VmRSS; start->end: first sample %.0f s after each start to the last, not judged;"
      "\nsettled: lowest sample of the %.0f s from %.0f s after the start -> lowest of the last "
      "%.0f s, judged):\n",
      o_.warmup_s, rule.window_ns * 1e-9, rule.settle_ns * 1e-9, rule.window_ns * 1e-9);
  for (const auto& [pid, m] : memory_.spans) {
    std::printf("  %-18s pid %-7d start->end %8ld -> %8ld kB %+6.1f %% over %5.0f s",
                m.process.c_str(), pid, m.first_kb, m.last_kb, m.growth_percent(),
                (m.last_ns - m.first_ns) * 1e-9);
    const bc::SettledGrowth g = bc::settled_growth(m, rule);
    if (g.available) {
      std::printf("  settled %8ld -> %8ld kB %+6.1f %% over %5.0f s\n", g.from_kb, g.to_kb,
                  g.percent(), (g.to_ns - g.from_ns) * 1e-9);
    } else {
      std::printf("  settled -\n");
    }
  }
  std::printf("\npublished vs recorded (stereoball record, seq numbers of each publisher run):\n");
  for (const auto& t : losses) {
    std::printf("  %-18s published %8llu recorded %8llu lost %llu (link down %llu) runs %llu\n",
                t.topic.c_str(), static_cast<unsigned long long>(t.published),
                static_cast<unsigned long long>(t.recorded),
                static_cast<unsigned long long>(t.lost),
                static_cast<unsigned long long>(t.lost_link_down),
                static_cast<unsigned long long>(t.publisher_runs));
  }
  std::printf("  recorded in all:");
  for (const auto& [topic, n] : recorded)
    std::printf(" %s %llu", topic.c_str(), static_cast<unsigned long long>(n));
  std::printf("\nfiles: %s\n", o_.out_dir.c_str());

  if (!o_.json_path.empty()) {
    std::ostringstream j;
    j << "{\n  \"command\": \"" << json_escape(command) << "\",\n  \"seed\": " << o_.seed
      << ",\n  \"minutes\": " << o_.minutes
      << ",\n  \"one_round\": " << (o_.one_round ? "true" : "false")
      << ",\n  \"namespaces\": " << (netns_ ? "true" : "false") << ",\n  \"namespaces_note\": \""
      << json_escape(netns_note) << "\",\n  \"passed\": " << (passed ? "true" : "false")
      << ",\n  \"tool_failures\": " << tool_failures_ << ",\n  \"faults\": {";
    bool first = true;
    for (const auto& [kind, n] : fault_counts_) {
      j << (first ? "" : ", ") << "\"" << kind << "\": " << n;
      first = false;
    }
    j << "},\n  \"restarts\": {";
    first = true;
    for (const auto& n : nodes_) {
      j << (first ? "" : ", ") << "\"" << n.name << "\": " << n.restarts;
      first = false;
    }
    j << "},\n  \"checks\": [";
    first = true;
    for (const auto& c : checks) {
      j << (first ? "\n" : ",\n") << "    {\"name\": \"" << c.name
        << "\", \"passed\": " << (c.passed ? "true" : "false")
        << ", \"applicable\": " << (c.applicable ? "true" : "false")
        << ", \"violations\": " << c.violations << ", \"detail\": \"" << json_escape(c.detail)
        << "\"}";
      first = false;
    }
    j << "\n  ],\n  \"memory\": [";
    first = true;
    for (const auto& [pid, m] : memory_.spans) {
      j << (first ? "\n" : ",\n") << "    {\"process\": \"" << m.process << "\", \"pid\": " << pid
        << ", \"first_kb\": " << m.first_kb << ", \"last_kb\": " << m.last_kb
        << ", \"span_s\": " << (m.last_ns - m.first_ns) * 1e-9
        << ", \"growth_percent\": " << m.growth_percent();
      const bc::SettledGrowth g = bc::settled_growth(m, rule);
      if (g.available) {
        j << ", \"settled_from_kb\": " << g.from_kb << ", \"settled_to_kb\": " << g.to_kb
          << ", \"settled_span_s\": " << (g.to_ns - g.from_ns) * 1e-9
          << ", \"settled_growth_percent\": " << g.percent();
      }
      j << "}";
      first = false;
    }
    j << "\n  ],\n  \"topics\": [";
    first = true;
    for (const auto& t : losses) {
      j << (first ? "\n" : ",\n") << "    {\"topic\": \"" << t.topic
        << "\", \"published\": " << t.published << ", \"recorded\": " << t.recorded
        << ", \"lost\": " << t.lost << ", \"lost_link_down\": " << t.lost_link_down
        << ", \"duplicates\": " << t.duplicates << ", \"publisher_runs\": " << t.publisher_runs
        << "}";
      first = false;
    }
    j << "\n  ],\n  \"recorded\": {";
    first = true;
    for (const auto& [topic, n] : recorded) {
      j << (first ? "" : ", ") << "\"" << topic << "\": " << n;
      first = false;
    }
    j << "}\n}\n";
    std::ofstream out(o_.json_path);
    out << j.str();
    if (!out) {
      std::fprintf(stderr, "stereoball bench chaos: cannot write %s\n", o_.json_path.c_str());
      return 2;
    }
  }
  return passed ? 0 : 1;
}

int Run::main() {
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
  std::printf("stereoball bench chaos: %s; files in %s\n", netns_note.c_str(), o_.out_dir.c_str());

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
  note("stopping");
  stop_all();

  // The base's events.
  std::vector<sb::base::BaseEvent> events;
  uint64_t bad_lines = 0;
  std::string first_bad;
  {
    std::ifstream in(base_log_);
    for (std::string line; std::getline(in, line);) {
      auto e = sb::base::parse_base_event(line);
      if (e) {
        events.push_back(*e);
      } else if (bad_lines++ == 0) {
        first_bad = e.error();
      }
    }
  }
  // The recording.
  std::map<std::string, std::vector<bc::SeqSample>> seqs;
  std::map<std::string, uint64_t> recorded;
  uint64_t undecodable = 0;
  std::string mcap_error;
  if (auto source = sb::recorder::FileSource::open(mcap_); !source) {
    mcap_error = source.error();
  } else {
    sb::recorder::McapReader reader(**source);
    if (auto st = reader.open(); !st) {
      mcap_error = st.error();
    } else {
      const auto& channels = reader.summary().channels;
      auto st2 = reader.for_each_message([&](const sb::recorder::MessageView& m) {
        const auto ch = channels.find(m.channel_id);
        if (ch == channels.end()) return true;
        const std::string& topic = ch->second.topic;
        if (topic != "sim/ground_truth" && topic != "cmd/velocity") {
          ++recorded[topic];
          return true;
        }
        const auto seq = bc::cdr_leading_u64(m.data);
        if (!seq) {
          ++undecodable;
          return true;
        }
        if (topic == "cmd/velocity" && *seq >= kRogueSeqBase) {
          ++recorded["cmd/velocity (rogue)"];
          return true;
        }
        ++recorded[topic];
        seqs[topic].push_back({*seq, static_cast<int64_t>(m.log_time_ns)});
        return true;
      });
      if (!st2) mcap_error = st2.error();
    }
  }
  bc::CheckParams params;
  std::vector<bc::Interval> link_excused;
  for (const auto& cut : timeline_.link_cuts)
    link_excused.push_back({cut.begin_ns, cut.end_ns + params.link_settle_ns});
  std::vector<bc::TopicLoss> losses;
  // Ground truth is published beside the recorder; commands come over the link.
  losses.push_back(bc::count_losses("sim/ground_truth", seqs["sim/ground_truth"], {}));
  losses.push_back(bc::count_losses("cmd/velocity", seqs["cmd/velocity"], link_excused));

  std::vector<bc::CheckResult> checks;
  checks.push_back(bc::check_no_unsafe_motion(events, params));
  checks.push_back(bc::check_estop_held(events, timeline_, params));
  bc::CheckResult lost = bc::check_none_lost(losses);
  if (!mcap_error.empty() || undecodable > 0) {
    lost.passed = false;
    lost.detail += "; recording: " + (mcap_error.empty() ? "" : mcap_error + ", ") +
                   std::to_string(undecodable) + " undecodable samples";
  }
  checks.push_back(lost);
  std::vector<bc::MemorySpan> spans;
  for (const auto& [pid, m] : memory_.spans) spans.push_back(m);
  checks.push_back(bc::check_memory(spans, memory_rule()));
  checks.push_back(bc::check_no_crashes(unexpected_));
  bc::CheckResult log_check;
  log_check.name = "base_log_readable";
  log_check.passed = !events.empty() && bad_lines <= 1;  // a SIGKILL may cut the last line
  log_check.detail = std::to_string(events.size()) + " events, " + std::to_string(bad_lines) +
                     " unreadable line(s)" + (first_bad.empty() ? "" : " (" + first_bad + ")");
  checks.push_back(log_check);
  return report(checks, losses, recorded, netns_note, faults.size());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball bench chaos: the whole system on the simulator follows the ball while seeded "
      "faults hit it (nodes killed and restarted, the link between two network namespaces cut, "
      "garbage on stereo/frame, the deployment key rotated, the e-stop engaged, commands signed "
      "with an unknown key). Checks: the robot never moved on stale or unauthenticated input, "
      "the e-stop held, memory per process, published vs recorded. Exit 1 when a check fails."};
  Options o;
  if (const char* d = std::getenv("STEREOBALL_DOMAIN")) o.domain = std::atoi(d);
  if (const char* p = std::getenv("STEREOBALL_PARTITION")) o.partition = p;
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
  CLI11_PARSE(app, argc, argv);

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  try {
    if (o.child == "flood") return run_flood(o);
    if (o.child == "rogue") return run_rogue(o);
    Run run(o);
    return run.main();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereoball bench chaos: %s\n", e.what());
    return 2;
  }
}
