// stereoball bench report: runs the acceptance benchmarks (or reads their saved output) and
// writes docs/benchmarks.md with the machine, date, commit and each table's exact command.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>
#include "common/util/cli11.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "bench_table.hpp"
#include "report.hpp"
#include "saved_outputs.hpp"

extern char** environ;

namespace {

namespace br = stereoball::bench_report;
namespace fs = std::filesystem;

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball-bench-report: %s\n", message.c_str());
  return 2;
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M UTC", &tm);
  return buf;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string first_line_of_command(const std::string& command) {
  std::string out;
  if (std::FILE* p = ::popen(command.c_str(), "r")) {
    char buf[256];
    if (std::fgets(buf, sizeof buf, p)) out = buf;
    ::pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out;
}

// /proc/loadavg's first three fields, or "" where there is none.
std::string load_average() {
  std::ifstream loadavg("/proc/loadavg");
  std::string a, b, c;
  if (loadavg >> a >> b >> c) return a + " " + b + " " + c;
  return "";
}

// The commit of the sources here, with "-dirty" when tracked files other than the report being
// written (OUT) are modified.
std::string current_commit(const std::string& out) {
  std::string commit = first_line_of_command("git rev-parse --short=12 HEAD 2>/dev/null");
  if (commit.empty()) return "unknown";
  const std::string status =
      "git status --porcelain --untracked-files=no -- . ':(exclude)" + out + "' 2>/dev/null";
  if (!first_line_of_command(status).empty()) commit += "-dirty";
  return commit;
}

br::MachineInfo machine_info(const std::string& commit, const std::string& report_command,
                             const std::string& out) {
  br::MachineInfo m;
  std::ifstream cpuinfo("/proc/cpuinfo");
  for (std::string line; std::getline(cpuinfo, line);) {
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos)
        m.cpu_model = line.substr(line.find_first_not_of(' ', colon + 1));
      break;
    }
  }
  if (m.cpu_model.empty()) m.cpu_model = "unknown CPU";
  m.cores = static_cast<int>(std::thread::hardware_concurrency());
  m.load = load_average();
  m.date_utc = utc_now();
  m.commit = commit;
  if (m.commit.empty()) m.commit = current_commit(out);
  m.report_command = report_command;
  return m;
}

// Runs ENTRY's program from BIN_DIR with its output saved in DIR; then reads it back. REPORT_PATH
// is the report being written (not a modification of the sources); MACHINE is recorded with it.
br::BenchOutcome run_bench(const br::BenchEntry& entry, const fs::path& bin_dir,
                           const std::string& report_path, const fs::path& dir, double timeout_min,
                           const std::string& machine) {
  br::BenchOutcome o;
  o.entry = &entry;
  const fs::path program = bin_dir / entry.program;
  if (!fs::exists(program)) {
    o.reason = entry.program + " is not built";
    return o;
  }
  std::vector<std::string> args{program.string()};
  args.insert(args.end(), entry.args.begin(), entry.args.end());
  std::string command = br::user_command(entry);
  const fs::path json = dir / (entry.name + ".json");
  fs::remove(json);
  if (entry.writes_json) {
    args.push_back("--json");
    args.push_back(json.string());
    command += " --json " + entry.name + ".json";
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string out = (dir / (entry.name + ".txt")).string();
  const std::string err = (dir / (entry.name + ".err")).string();
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, out.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, err.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  std::fprintf(stderr, "stereoball-bench-report: running %s\n", command.c_str());
  const std::string date = utc_now();
  const std::string load = load_average();
  const std::string commit = current_commit(report_path);
  // Until NAME.cmd records this run's end, a reader of the folder sees it running (or, should
  // this report be killed with it, incomplete), never the previous run's end with new output.
  const fs::path cmd_path = dir / (entry.name + ".cmd");
  const fs::path marker_path = dir / (entry.name + ".running");
  fs::remove(cmd_path);
  fs::remove(marker_path);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc == 0) std::ofstream(marker_path) << br::running_marker_text({pid, entry.program, date});
  std::string status = "ok";
  if (rc != 0) {
    status = "could not start: " + std::string(std::strerror(rc));
  } else {
    const auto deadline = start + std::chrono::duration<double>(timeout_min * 60.0);
    int ws = 0;
    for (;;) {
      const pid_t done = waitpid(pid, &ws, WNOHANG);
      if (done == pid) break;
      if (std::chrono::steady_clock::now() > deadline) {
        kill(pid, SIGTERM);
        waitpid(pid, &ws, 0);
        status = "stopped after the " + std::to_string(static_cast<int>(timeout_min)) +
                 " min time limit";
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    if (status == "ok" && !(WIFEXITED(ws) && WEXITSTATUS(ws) == 0)) {
      status = WIFEXITED(ws) ? "exit status " + std::to_string(WEXITSTATUS(ws))
                             : "killed by signal " + std::to_string(WTERMSIG(ws));
      const std::string e = read_file(err);
      if (!e.empty()) status += ": " + e.substr(0, e.find('\n'));
    }
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::ofstream meta(cmd_path);
  meta << command << "\n"
       << date << "\n"
       << status << "\n"
       << seconds << "\n"
       << load << "\n"
       << commit << "\n"
       << machine << "\n";
  meta.close();
  fs::remove(marker_path);
  return br::read_saved(entry, dir);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Runs the acceptance benchmarks (or reads the output they saved) and writes "
      "docs/benchmarks.md: machine, date, commit, and each bench's own output under the exact "
      "command that produced it. Without --only it runs the cheap benches (a few minutes each on "
      "two cores) and reports the others as not run, with their commands; run it under `nice` "
      "on a shared machine.",
      "stereoball-bench-report"};
  std::string out = "docs/benchmarks.md", outputs = "bench-outputs", from, commit;
  std::vector<std::string> only;
  bool all = false, list = false;
  double timeout_min = 60;
  app.add_option("--out", out, "the report to write")->capture_default_str();
  app.add_option("--outputs", outputs,
                 "folder where each bench's output is saved (NAME.txt, NAME.cmd, NAME.json)")
      ->capture_default_str();
  app.add_option(
      "--from", from,
      "run nothing unless --only says so: read the outputs saved in this folder "
      "(NAME.txt, and NAME.cmd with command, date, status, seconds, load, commit, machine)");
  app.add_option("--only", only, "run only these benches (repeatable; see --list)");
  app.add_flag("--all", all, "run every bench, the slow ones too (hours)");
  app.add_flag("--list", list, "print the benches and their commands, then exit");
  app.add_option("--timeout-min", timeout_min, "stop a bench that runs longer than this")
      ->check(CLI::Range(1.0, 24 * 60.0))
      ->capture_default_str();
  app.add_option("--commit", commit, "commit to name (default: git rev-parse HEAD here)");
  CLI11_PARSE(app, argc, argv);

  if (list) {
    for (const auto& e : br::bench_table())
      std::printf("%-24s %-5s %s\n", e.name.c_str(), e.cheap ? "cheap" : "slow",
                  br::user_command(e).c_str());
    return 0;
  }
  for (const auto& name : only) {
    if (!br::find_bench(name)) return fail("no bench named '" + name + "' (see --list)");
  }
  const fs::path dir = from.empty() ? fs::path(outputs) : fs::path(from);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return fail("cannot create '" + dir.string() + "': " + ec.message());
  const fs::path bin_dir = fs::canonical("/proc/self/exe", ec).parent_path();
  if (ec) return fail("cannot find my own folder: " + ec.message());

  std::string report_command = "stereoball bench report";
  for (int i = 1; i < argc; ++i) report_command += std::string(" ") + argv[i];
  const br::MachineInfo machine = machine_info(commit, report_command, out);

  std::vector<br::BenchOutcome> outcomes;
  for (const auto& e : br::bench_table()) {
    const bool chosen = !only.empty() ? std::find(only.begin(), only.end(), e.name) != only.end()
                                      : from.empty() && (all || e.cheap);
    br::BenchOutcome o =
        chosen ? run_bench(e, bin_dir, out, dir, timeout_min, br::machine_text(machine))
               : br::read_saved(e, dir);
    if (!chosen && o.state == br::BenchOutcome::State::kNotRun) {
      o.reason = !from.empty() ? "no output saved in " + from
                 : e.cheap     ? "not selected"
                               : "slow: minutes to hours on two cores; --only " + e.name;
    }
    outcomes.push_back(std::move(o));
  }
  const fs::path out_path(out);
  if (out_path.has_parent_path()) fs::create_directories(out_path.parent_path(), ec);
  std::ofstream md(out_path);
  md << br::render_report(machine, outcomes);
  md.close();
  if (!md) return fail("writing '" + out + "' failed");
  using State = br::BenchOutcome::State;
  auto count = [&](State state) {
    return std::count_if(outcomes.begin(), outcomes.end(),
                         [&](const br::BenchOutcome& o) { return o.state == state; });
  };
  std::printf(
      "wrote %s: %ld bench(es) with figures, %ld failed, %ld incomplete, %ld running, %ld not "
      "run\n",
      out.c_str(), count(State::kRan), count(State::kFailed), count(State::kIncomplete),
      count(State::kRunning), count(State::kNotRun));
  return count(State::kFailed) + count(State::kIncomplete) > 0 ? 1 : 0;
}
