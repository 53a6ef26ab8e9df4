// `stereoball`: the umbrella command. `stereoball A B ...` runs `stereoball-A-B ...` if that
// program exists beside this one, else `stereoball-A B ...` (like git's subcommands), so each
// subcommand is its own small program owned by its component.

#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Subcommand {
  std::string_view name;
  std::string_view summary;
};

constexpr std::array<Subcommand, 18> kKnown = {{
    {"demo", "run the whole system on the simulator and write a report"},
    {"launch", "start and supervise a deploy/ profile"},
    {"view", "live viewer in the browser and Foxglove WebSocket server, one port"},
    {"foxglove", "the same as view (Foxglove: connect to ws://HOST:PORT/)"},
    {"topic", "list, echo and measure topics (list | echo | hz)"},
    {"detect", "detect circles in image files"},
    {"bench", "benchmarks (detect | tracking | closed-loop | chaos | ...)"},
    {"calibrate", "stereo calibration from chessboard image pairs"},
    {"sim", "run a simulator scenario headless, write frames to disk"},
    {"record", "record topics to an MCAP file"},
    {"play", "play an MCAP file back into the system"},
    {"info", "summarise an MCAP file"},
    {"cameras", "list V4L2 cameras"},
    {"estop", "engage, release (with confirmation) or show the emergency stop"},
    {"doctor", "check a running deployment, one line per check with the fix"},
    {"keys", "deployment keys: init | show | rotate"},
    {"version", "print the version"},
    {"help", "this list"},
}};

// Where the subcommand programs live: beside this one in a build tree, in
// <prefix>/libexec/stereoball when installed (they are not commands of their own on PATH).
#ifndef SB_PROGRAMS_REL
#define SB_PROGRAMS_REL "../libexec/stereoball"
#endif

fs::path programs_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  const fs::path self = ec ? fs::path(".") : exe.parent_path();
  const fs::path installed = self / SB_PROGRAMS_REL;
  return fs::is_directory(installed, ec) ? fs::weakly_canonical(installed, ec) : self;
}

void print_usage(const fs::path& dir) {
  std::printf("usage: stereoball <command> [args...]\n\ncommands:\n");
  for (const auto& sub : kKnown) {
    // bench has only nested programs (stereoball-bench-detect, ...).
    const std::string program(sub.name == "foxglove" ? "view" : sub.name);
    const bool present = sub.name == "help" || sub.name == "version" || sub.name == "bench" ||
                         fs::exists(dir / ("stereoball-" + program));
    std::printf("  %-10s %.*s%s\n", std::string(sub.name).c_str(),
                static_cast<int>(sub.summary.size()), sub.summary.data(),
                present ? "" : "  (not built)");
  }
  std::printf("\n`stereoball <command> --help` shows the options of a command.\n");
}

[[noreturn]] void exec(const fs::path& program, const std::vector<std::string>& args) {
  std::vector<char*> argv;
  std::string name = program.string();
  argv.push_back(name.data());
  std::vector<std::string> copy = args;
  for (auto& arg : copy) argv.push_back(arg.data());
  argv.push_back(nullptr);
  execv(program.c_str(), argv.data());
  std::perror(("stereoball: cannot run " + name).c_str());
  std::_Exit(127);
}

}  // namespace

int main(int argc, char** argv) {
  const fs::path dir = programs_dir();
  if (argc < 2 || std::string_view(argv[1]) == "help" || std::string_view(argv[1]) == "--help" ||
      std::string_view(argv[1]) == "-h") {
    print_usage(dir);
    return argc < 2 ? 1 : 0;
  }
  // `stereoball foxglove` is `stereoball view`: one process serves the page and Foxglove.
  const std::string command = std::string_view(argv[1]) == "foxglove" ? "view" : argv[1];
  if (command == "version" || command == "--version") {
    std::printf("stereoball %s\n", SB_VERSION);
    return 0;
  }
  std::vector<std::string> rest(argv + 2, argv + argc);
  if (!rest.empty() && rest.front().rfind("-", 0) != 0) {
    const fs::path nested = dir / ("stereoball-" + command + "-" + rest.front());
    if (fs::exists(nested)) exec(nested, {rest.begin() + 1, rest.end()});
  }
  const fs::path direct = dir / ("stereoball-" + command);
  if (fs::exists(direct)) exec(direct, rest);
  std::fprintf(stderr, "stereoball: unknown command '%s' (see `stereoball help`)\n",
               (command + (rest.empty() ? "" : " " + rest.front())).c_str());
  return 2;
}
