// spawn, run_command and read_rss for the chaos run's processes, and the network namespaces:
// created with iproute2, the link between them cut and restored, removed at the end.
#include "chaos_processes.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <thread>
#include <tuple>

namespace sb = stereoball;
namespace fs = std::filesystem;

namespace stereoball::bench_chaos {

volatile sig_atomic_t g_stop = 0;

namespace {

std::string ip_program() {
  for (const char* p : {"/usr/sbin/ip", "/sbin/ip", "/usr/bin/ip", "/bin/ip"}) {
    if (fs::exists(p)) return p;
  }
  return "";
}

}  // namespace

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

sb::Status Namespaces::make() {
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

bool Namespaces::set_link(bool up) const {
  return run_command({ip, "-n", robot, "link", "set", robot_iface, up ? "up" : "down"}, "/dev/null",
                     10 * kS) == 0;
}

Namespaces::~Namespaces() {
  if (!created) return;
  for (const auto& ns : {robot, workstation}) {
    run_command({ip, "netns", "delete", ns}, "/dev/null", 10 * kS);
  }
}

}  // namespace stereoball::bench_chaos
