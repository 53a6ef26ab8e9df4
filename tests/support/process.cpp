#include "process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace stereoball::testing {

namespace {
int decode_status(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}
}  // namespace

Process Process::start(const std::vector<std::string>& argv,
                       const std::vector<std::string>& extra_env) {
  char log_template[] = "/tmp/sb-test-proc-XXXXXX";
  const int log_fd = mkstemp(log_template);
  if (log_fd < 0) throw std::runtime_error("cannot create log file for child process");
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) env.emplace_back(*e);
  for (const auto& extra : extra_env) env.push_back(extra);
  std::vector<char*> c_argv;
  std::vector<std::string> argv_copy = argv;
  for (auto& a : argv_copy) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);
  std::vector<char*> c_env;
  for (auto& e : env) c_env.push_back(e.data());
  c_env.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    dup2(log_fd, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    const int null_fd = open("/dev/null", O_RDONLY);
    dup2(null_fd, STDIN_FILENO);
    // Children must not inherit a blocked signal mask from the test.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    execve(c_argv[0], c_argv.data(), c_env.data());
    dprintf(log_fd, "exec %s failed\n", c_argv[0]);
    _exit(127);
  }
  close(log_fd);
  return Process(pid, log_template);
}

Process::Process(Process&& other) noexcept
    : pid_(std::exchange(other.pid_, -1)),
      log_path_(std::move(other.log_path_)),
      exit_code_(other.exit_code_) {}

Process::~Process() {
  if (pid_ > 0 && !exit_code_) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  if (!log_path_.empty()) std::filesystem::remove(log_path_);
}

bool Process::running() {
  if (exit_code_) return false;
  int status = 0;
  const pid_t r = waitpid(pid_, &status, WNOHANG);
  if (r == pid_) {
    exit_code_ = decode_status(status);
    return false;
  }
  return true;
}

void Process::signal(int sig) {
  if (running()) kill(pid_, sig);
}

std::optional<int> Process::wait_for_exit(std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  while (running()) {
    if (std::chrono::steady_clock::now() >= deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return exit_code_;
}

std::string Process::output() const {
  std::ifstream in(log_path_);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

bool Process::wait_for_output(const std::string& text, std::chrono::milliseconds timeout) const {
  return eventually([&] { return output().find(text) != std::string::npos; }, timeout);
}

std::pair<int, std::string> run(const std::vector<std::string>& argv,
                                std::chrono::milliseconds timeout,
                                const std::vector<std::string>& extra_env) {
  Process p = Process::start(argv, extra_env);
  auto code = p.wait_for_exit(timeout);
  return {code.value_or(-1), p.output()};
}

std::string bin(const std::string& name) {
  const char* dir = std::getenv("SB_BIN_DIR");
  return std::string(dir ? dir : SB_BIN_DIR) + "/" + name;
}

std::string source_path(const std::string& relative) {
  const char* dir = std::getenv("SB_SOURCE_DIR");
  return std::string(dir ? dir : SB_SOURCE_DIR) + "/" + relative;
}

int test_domain() {
  const char* text = std::getenv("STEREOBALL_DOMAIN");
  return text ? std::atoi(text) : 0;
}

std::string unique_partition() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "test";
  return "sbtest." + name + "." + std::to_string(getpid());
}

bool eventually(const std::function<bool()>& pred, std::chrono::milliseconds timeout) {
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  for (;;) {
    if (pred()) return true;
    if (std::chrono::steady_clock::now() >= deadline) return pred();
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
}

std::optional<long> memory_kb(pid_t pid, const std::string& field) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  }
  return std::nullopt;
}

std::string temp_dir() {
  char tmpl[] = "/tmp/sb-test-XXXXXX";
  const char* dir = mkdtemp(tmpl);
  if (!dir) throw std::runtime_error("mkdtemp failed");
  return dir;
}

std::string make_key_file(const std::string& dir, const std::string& name) {
  const std::string path = dir + "/" + name;
  auto [code, output] =
      run({bin("stereoball-keys"), "init", "--file", path}, std::chrono::seconds(20));
  EXPECT_EQ(code, 0) << "stereoball-keys init --file " << path << ": " << output;
  return path;
}

}  // namespace stereoball::testing
