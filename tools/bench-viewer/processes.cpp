#include "processes.hpp"

#include <dirent.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace stereoball::bench {
namespace {

// Fields of a /proc/.../stat file after the command name (which may contain spaces).
std::vector<std::string> stat_fields(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  if (!std::getline(f, line)) return {};
  const auto close = line.rfind(')');
  if (close == std::string::npos || close + 2 > line.size()) return {};
  std::istringstream rest(line.substr(close + 2));
  std::vector<std::string> fields;
  for (std::string field; rest >> field;) fields.push_back(field);
  return fields;
}

std::vector<std::string> stat_fields(pid_t pid) {
  return stat_fields("/proc/" + std::to_string(pid) + "/stat");
}

// utime + stime of stat fields ([0] is the state: they are [11] and [12]), seconds.
std::optional<double> cpu_of(const std::vector<std::string>& fields) {
  if (fields.size() < 13) return std::nullopt;
  return (std::stod(fields[11]) + std::stod(fields[12])) /
         static_cast<double>(sysconf(_SC_CLK_TCK));
}

}  // namespace

std::optional<double> cpu_seconds(pid_t pid) {
  return cpu_of(stat_fields(pid));
}

std::map<std::string, double> thread_cpu_seconds(pid_t pid) {
  std::map<std::string, double> out;
  std::error_code ec;
  const std::string task = "/proc/" + std::to_string(pid) + "/task";
  for (auto it = std::filesystem::directory_iterator(task, ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec)) {
    std::ifstream comm(it->path() / "comm");
    std::string name;
    std::getline(comm, name);
    if (const auto cpu = cpu_of(stat_fields((it->path() / "stat").string())))
      out[name.empty() ? "?" : name] += *cpu;
  }
  return out;
}

std::string process_name(pid_t pid) {
  std::ifstream comm("/proc/" + std::to_string(pid) + "/comm");
  std::string name;
  std::getline(comm, name);
  return name.empty() ? "?" : name;
}

std::optional<double> rss_mb(pid_t pid) {
  std::ifstream f("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return std::nullopt;
}

std::vector<pid_t> children_of(pid_t pid) {
  std::vector<pid_t> out;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t candidate = std::stoi(name);
    const auto fields = stat_fields(candidate);  // [1] is the parent pid
    if (fields.size() > 1 && std::stoi(fields[1]) == pid) out.push_back(candidate);
  }
  return out;
}

double load_average() {
  std::ifstream f("/proc/loadavg");
  double one = 0;
  f >> one;
  return one;
}

}  // namespace stereoball::bench
