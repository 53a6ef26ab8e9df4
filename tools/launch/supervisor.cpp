#include "supervisor.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <string_view>
#include <thread>

#include "common/util/deployment.hpp"

extern char** environ;

namespace stereoball::launch {
namespace {
int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}
int64_t mono_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
}  // namespace

Supervisor::Supervisor(Profile profile, SupervisorOptions options, EventSink events)
    : profile_(std::move(profile)), options_(std::move(options)), events_(std::move(events)) {
  log_fd_ = ::open(options_.log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  for (const auto& node : profile_.nodes) states_.push_back(NodeState{node.name});
  restart_due_ns_.assign(states_.size(), 0);
  started_ns_.assign(states_.size(), 0);
}

Supervisor::~Supervisor() {
  stop_all();
  if (log_fd_ >= 0) ::close(log_fd_);
}

pid_t Supervisor::spawn(const NodeSpec& spec) {
  std::vector<std::string> args{options_.bin_dir + "/" + spec.program};
  args.insert(args.end(), spec.args.begin(), spec.args.end());
  args.insert(args.end(), options_.extra_args.begin(), options_.extra_args.end());
  if (auto it = options_.node_args.find(spec.name); it != options_.node_args.end()) {
    args.insert(args.end(), it->second.begin(), it->second.end());
  }
  std::vector<std::string> env;
  // The profile's DDS configuration replaces an inherited one (a duplicate variable would let
  // the inherited value win).
  const bool profile_sets_uri = !profile_.cyclonedds_config.empty();
  for (char** e = environ; *e; ++e) {
    if (profile_sets_uri && std::string_view(*e).rfind("CYCLONEDDS_URI=", 0) == 0) continue;
    env.emplace_back(*e);
  }
  if (profile_sets_uri)
    env.push_back("CYCLONEDDS_URI=" + deployment::file_uri(profile_.cyclonedds_config));
  std::vector<char*> c_args, c_env;
  for (auto& a : args) c_args.push_back(a.data());
  c_args.push_back(nullptr);
  for (auto& e : env) c_env.push_back(e.data());
  c_env.push_back(nullptr);
  const pid_t supervisor_pid = getpid();
  const pid_t pid = fork();
  if (pid == 0) {
    // The node goes down with the supervisor however it dies (even SIGKILL); the check after
    // covers a supervisor that died before prctl ran.
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != supervisor_pid) _exit(0);
    if (log_fd_ >= 0) {
      dup2(log_fd_, STDOUT_FILENO);
      dup2(log_fd_, STDERR_FILENO);
    }
    const int null_fd = ::open("/dev/null", O_RDONLY);
    dup2(null_fd, STDIN_FILENO);
    // Own process group: Ctrl-C in the terminal reaches the supervisor only, which then
    // stops the nodes in order.
    setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    execve(c_args[0], c_args.data(), c_env.data());
    _exit(127);
  }
  return pid;
}

Result<bool> Supervisor::start_all(int64_t now_ns) {
  for (size_t i = 0; i < profile_.nodes.size(); ++i) {
    const auto& spec = profile_.nodes[i];
    const std::string program = options_.bin_dir + "/" + spec.program;
    if (!std::filesystem::exists(program)) {
      if (spec.optional) {
        states_[i].skipped = true;
        events_(spec.name + ": skipped (" + spec.program + " is not built)");
        continue;
      }
      return Error{spec.name + ": program " + program +
                   " not found (build first: bash run.sh build)"};
    }
    states_[i].pid = spawn(spec);
    started_ns_[i] = now_ns;
    events_(spec.name + ": started (pid " + std::to_string(states_[i].pid) + ")");
  }
  return true;
}

void Supervisor::on_exit(size_t i, int status, int64_t now_ns) {
  auto& st = states_[i];
  st.pid = -1;
  st.last_exit_code = decode_status(status);
  // Any exit here is unexpected, a clean one too: only stop_all() stops nodes.
  std::string how = "exited with code " + std::to_string(st.last_exit_code);
  if (WIFSIGNALED(status)) how += " (" + std::string(strsignal(WTERMSIG(status))) + ")";
  if (!profile_.nodes[i].restart) {
    events_(st.name + ": " + how + "; not restarted (restart: false)");
    st.given_up = true;
    return;
  }
  if (now_ns - started_ns_[i] >= options_.stable_after_ns) st.restarts_in_row = 0;
  if (st.restarts_in_row >= options_.max_restarts) {
    st.given_up = true;
    events_(st.name + ": " + how + ", gave up after " + std::to_string(st.restarts_in_row) +
            " restarts in a row");
    return;
  }
  // Back-off doubles so a node that cannot start does not spin.
  int64_t delay_ns = options_.restart_backoff_ns;
  for (int k = 0; k < st.restarts_in_row && delay_ns < options_.max_backoff_ns; ++k) delay_ns *= 2;
  delay_ns = std::min(delay_ns, options_.max_backoff_ns);
  restart_due_ns_[i] = now_ns + delay_ns;
  events_(st.name + ": " + how + ", restarting in " + std::to_string(delay_ns / 1'000'000) +
          " ms (restart " + std::to_string(st.restarts_in_row + 1) + " of at most " +
          std::to_string(options_.max_restarts) + " in a row)");
}

void Supervisor::poll(int64_t now_ns) {
  for (size_t i = 0; i < states_.size(); ++i) {
    auto& st = states_[i];
    if (st.pid > 0) {
      int status = 0;
      if (waitpid(st.pid, &status, WNOHANG) == st.pid) on_exit(i, status, now_ns);
    } else if (restart_due_ns_[i] > 0 && now_ns >= restart_due_ns_[i]) {
      restart_due_ns_[i] = 0;
      ++st.restarts;
      ++st.restarts_in_row;
      st.pid = spawn(profile_.nodes[i]);
      started_ns_[i] = now_ns;
      events_(st.name + ": restarted (pid " + std::to_string(st.pid) + ")");
    }
  }
}

bool Supervisor::stop_all() {
  bool clean = true;
  for (auto& st : states_) {
    if (st.pid > 0) kill(st.pid, SIGTERM);
  }
  std::fill(restart_due_ns_.begin(), restart_due_ns_.end(), 0);
  const int64_t deadline = mono_ns() + options_.stop_grace_ns;
  for (auto& st : states_) {
    while (st.pid > 0) {
      int status = 0;
      if (waitpid(st.pid, &status, WNOHANG) == st.pid) {
        st.last_exit_code = decode_status(status);
        if (st.last_exit_code != 0) clean = false;
        st.pid = -1;
      } else if (mono_ns() >= deadline) {
        kill(st.pid, SIGKILL);
        waitpid(st.pid, &status, 0);
        events_(st.name + ": did not stop within the grace period, killed");
        st.last_exit_code = 128 + SIGKILL;
        st.pid = -1;
        clean = false;
      } else {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    }
  }
  return clean;
}

void Supervisor::signal_node(const std::string& name, int sig) {
  for (auto& st : states_) {
    if (st.name == name && st.pid > 0) kill(st.pid, sig);
  }
}

}  // namespace stereoball::launch
