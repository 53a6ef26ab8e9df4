#include "browser.hpp"

#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>

#include "processes.hpp"

extern char** environ;

namespace stereoball::bench {
namespace {

constexpr const char* kNode = "/usr/bin/node";
constexpr const char* kChromium = "/usr/bin/chromium";

std::string script() {
  return sibling_program("stereoball-bench-viewer-browser.mjs");
}

}  // namespace

Status Browser::available() {
  if (!std::filesystem::exists(kNode)) return Error{std::string(kNode) + " is not installed"};
  if (!std::filesystem::exists(kChromium))
    return Error{std::string(kChromium) + " is not installed"};
  if (!std::filesystem::exists(script())) return Error{script() + " is missing"};
  return {};
}

Browser::Browser(const std::string& url) {
  int in[2], out[2];
  if (pipe(in) != 0 || pipe(out) != 0) {
    error_ = "cannot create pipes";
    return;
  }
  const std::string s = script();
  std::vector<std::string> args = {kNode, "--no-warnings", "--experimental-websocket", s,
                                   url,   kChromium};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addclose(&actions, in[1]);
  posix_spawn_file_actions_addclose(&actions, out[0]);
  if (posix_spawn(&pid_, kNode, &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
  posix_spawn_file_actions_destroy(&actions);
  close(in[0]);
  close(out[1]);
  to_node_ = in[1];
  from_node_ = out[0];
  if (pid_ < 0) {
    error_ = "cannot start node";
    return;
  }
  const auto line = read_line(120);
  if (!line || *line != "ready") error_ = line ? *line : "the page drew no images in 120 s";
}

Browser::~Browser() {
  if (to_node_ >= 0) close(to_node_);
  if (from_node_ >= 0) close(from_node_);
  if (pid_ <= 0) return;
  for (int i = 0; i < 100; ++i) {  // node kills Chromium and exits once stdin closes
    if (waitpid(pid_, nullptr, WNOHANG) == pid_) return;
    usleep(100'000);
  }
  kill(pid_, SIGKILL);
  waitpid(pid_, nullptr, 0);
}

std::optional<std::string> Browser::read_line(double timeout_s) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    const auto nl = buffered_.find('\n');
    if (nl != std::string::npos) {
      std::string line = buffered_.substr(0, nl);
      buffered_.erase(0, nl + 1);
      return line;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        end - std::chrono::steady_clock::now());
    if (left.count() <= 0) return std::nullopt;
    pollfd p{from_node_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
    char buf[65536];
    const ssize_t n = read(from_node_, buf, sizeof buf);
    if (n <= 0) return std::nullopt;
    buffered_.append(buf, static_cast<size_t>(n));
  }
}

bool Browser::mark() {
  if (!error_.empty() || write(to_node_, "mark\n", 5) != 5) return false;
  const auto line = read_line(30);
  return line && *line == "marked";
}

std::optional<BrowserResult> Browser::finish() {
  if (!error_.empty()) return std::nullopt;
  if (write(to_node_, "report\n", 7) != 7) return std::nullopt;
  const auto line = read_line(60);
  if (!line) return std::nullopt;
  try {
    const auto j = nlohmann::json::parse(*line);
    return BrowserResult{j.at("images").get<uint64_t>(), j.at("skipped").get<uint64_t>(),
                         j.at("latenciesMs").get<std::vector<double>>(),
                         j.at("stages").get<std::vector<std::vector<double>>>()};
  } catch (const std::exception&) {
    error_ = *line;
    return std::nullopt;
  }
}

}  // namespace stereoball::bench
