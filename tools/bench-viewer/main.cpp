// stereoball bench viewer: what `stereoball view` costs, on the demo (default) or a synthetic
// 640x480 stereo stream. Per case (no viewer; viewer with 0, 1, 2, 5 page-like WebSocket
// clients; one headless Chromium showing the page), repeated --repeats times in rounds: the
// viewer's CPU (% of one core, median), the robot processes' CPU, images per client,
// capture -> client latency p50/p90 and the viewer's resident memory. --soak S instead
// connects and disconnects --clients clients in a loop for S seconds and prints the viewer's
// memory every minute and its slope. --watch P only starts a viewer on partition P with
// --clients page clients (someone watching another program's robot).

#include <unistd.h>

#include "common/util/cli11.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <regex>
#include <thread>
#include <vector>

#include "browser.hpp"
#include "common/dds/participant.hpp"
#include "common/util/install_layout.hpp"
#include "processes.hpp"
#include "source.hpp"
#include "view_client.hpp"

namespace sb = stereoball;
namespace bench = stereoball::bench;
namespace vc = stereoball::view_client;
using namespace std::chrono_literals;

namespace {

struct Options {
  std::string source = "demo";
  std::string scenario = "ball_rolling_away";
  int width = 640, height = 480;
  double rate_hz = 30;
  double phase_s = 10;
  int repeats = 3;
  std::vector<int> clients;
  bool browser = true;
  double soak_s = 0;
  std::string watch_partition;  // --watch: only a viewer with clients on someone else's robot
  double watch_s = 0;
  std::vector<std::string> viewer_args;
  bool jpeg = false;            // synthetic frames as from JPEG cameras
  std::string baseline_viewer;  // another stereoball-view build, measured side by side
  int domain = sb::dds::domain_from_env(0);
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : (v[n / 2 - 1] + v[n / 2]) / 2;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(std::lround(q * static_cast<double>(v.size() - 1)))];
}

double sum_cpu_seconds(const std::vector<pid_t>& pids) {
  double total = 0;
  for (pid_t p : pids) total += bench::cpu_seconds(p).value_or(0);
  return total;
}

using vc::stats_counter;

// Pairs the viewer made for its clients: encoded from raw frames, or forwarded from the
// publisher's stereo/preview (a viewer built before previews reports no such counter).
long pairs_made(int port) {
  return stats_counter(port, "pairs_encoded") +
         std::max(0L, stats_counter(port, "pairs_from_preview"));
}

// A running stereoball-view and its port.
struct Viewer {
  std::unique_ptr<bench::Child> child;
  int port = 0;
};

std::optional<Viewer> start_viewer(const Options& o, const std::string& program,
                                   const std::string& partition, const std::string& log_prefix) {
  // A log of its own: the address found in it must be this viewer's.
  static int started = 0;
  const std::string log = log_prefix + "-" + std::to_string(++started) + ".log";
  std::vector<std::string> argv = {
      program, "--port", "0", "--domain", std::to_string(o.domain), "--partition", partition};
  argv.insert(argv.end(), o.viewer_args.begin(), o.viewer_args.end());
  Viewer v{std::make_unique<bench::Child>(argv, log), 0};
  const auto port = v.child->wait_for_log(std::regex(R"(viewer: http://127\.0\.0\.1:(\d+)/)"), 60);
  if (!port) return std::nullopt;
  v.port = std::stoi(*port);
  return v;
}

// One measured case: what is connected while the viewer's and the robot's CPU are sampled.
struct Case {
  std::string name;
  bool viewer = true;
  int clients = 0;
  bool browser = false;
  std::string program;  // the stereoball-view to run
};

// Stages of an image's way, ms: capture -> taken by the viewer -> encoded -> received by the
// client -> decoded -> drawn (the last two in Chromium only).
constexpr const char* kStageNames[] = {"capture→taken", "encode", "→client", "decode", "→drawn"};
constexpr size_t kStages = std::size(kStageNames);

struct Sample {
  double viewer_cpu = NAN, robot_cpu = NAN, images_per_client_s = NAN, rss_mb = NAN;
  double frames_hz = NAN, encoded_per_s = NAN;
  std::vector<double> latencies_ms;
  std::vector<double> stages_ms[kStages];
  std::map<std::string, double> viewer_threads_cpu;   // % of one core per thread name
  std::map<std::string, double> robot_processes_cpu;  // % of one core per robot process name
};

class Measurer {
 public:
  Measurer(const Options& o, const bench::Source& source, bench::FrameRate& frames)
      : o_(o), source_(source), frames_(frames) {}

  // Connects what the case needs, waits for it to settle, samples for phase_s.
  std::optional<Sample> run(const Case& c, const Viewer* viewer) {
    std::vector<std::unique_ptr<vc::WsClient>> clients;
    std::unique_ptr<bench::Browser> browser;
    if (viewer) {
      for (int i = 0; i < c.clients; ++i) {
        clients.push_back(std::make_unique<vc::WsClient>(viewer->port, vc::WsClient::Kind::kPage));
        if (!clients.back()->connected()) {
          std::printf("  client %d could not connect to port %d\n", i + 1, viewer->port);
          return std::nullopt;
        }
      }
      if (c.browser) {
        browser = std::make_unique<bench::Browser>(
            "http://127.0.0.1:" + std::to_string(viewer->port) + "/");
        if (!browser->error().empty()) {
          std::printf("  browser: %s\n", browser->error().c_str());
          return std::nullopt;
        }
      }
    }
    std::this_thread::sleep_for(2s);  // frame reader created, first frames encoded
    const auto robot = source_.robot_processes();
    const pid_t vp = viewer ? viewer->child->pid() : -1;
    const double viewer0 = viewer ? bench::cpu_seconds(vp).value_or(NAN) : NAN;
    const auto threads0 = viewer ? bench::thread_cpu_seconds(vp) : std::map<std::string, double>{};
    const double robot0 = sum_cpu_seconds(robot);
    std::map<pid_t, double> robot_each0;
    for (pid_t r : robot) robot_each0[r] = bench::cpu_seconds(r).value_or(NAN);
    const long encoded0 = viewer ? pairs_made(viewer->port) : 0;
    uint64_t images0 = 0;
    for (auto& cl : clients) images0 += cl->images();
    std::vector<size_t> lat0;
    for (auto& cl : clients) lat0.push_back(cl->timings().size());
    if (browser && !browser->mark()) {
      std::printf("  browser: did not answer\n");
      return std::nullopt;
    }
    frames_.restart();
    const auto t0 = std::chrono::steady_clock::now();
    std::this_thread::sleep_for(std::chrono::duration<double>(o_.phase_s));
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    Sample s;
    if (viewer) {
      s.viewer_cpu = (bench::cpu_seconds(vp).value_or(NAN) - viewer0) / wall * 100;
      for (const auto& [name, cpu] : bench::thread_cpu_seconds(vp)) {
        const auto before = threads0.find(name);
        s.viewer_threads_cpu[name] =
            (cpu - (before == threads0.end() ? 0 : before->second)) / wall * 100;
      }
    }
    if (!robot.empty()) s.robot_cpu = (sum_cpu_seconds(robot) - robot0) / wall * 100;
    for (pid_t r : robot)
      s.robot_processes_cpu[bench::process_name(r)] +=
          (bench::cpu_seconds(r).value_or(NAN) - robot_each0[r]) / wall * 100;
    s.frames_hz = frames_.rate_hz();
    if (viewer) {
      s.rss_mb = bench::rss_mb(vp).value_or(NAN);
      s.encoded_per_s = (pairs_made(viewer->port) - encoded0) / wall;
    }
    uint64_t images = 0;
    for (size_t i = 0; i < clients.size(); ++i) {
      images += clients[i]->images();
      const auto t = clients[i]->timings();
      for (size_t k = lat0[i]; k < t.size(); ++k) {
        s.latencies_ms.push_back(t[k].capture_to_received);
        s.stages_ms[0].push_back(t[k].capture_to_taken);
        s.stages_ms[1].push_back(t[k].taken_to_encoded);
        s.stages_ms[2].push_back(t[k].encoded_to_received);
      }
    }
    if (!clients.empty()) s.images_per_client_s = (images - images0) / wall / clients.size();
    if (browser) {
      const auto r = browser->finish();
      if (!r) {
        std::printf("  browser: %s\n", browser->error().c_str());
        return std::nullopt;
      }
      s.images_per_client_s = r->images / wall;
      s.latencies_ms = r->latencies_ms;
      for (const auto& stages : r->stages_ms)
        for (size_t k = 0; k < kStages && k < stages.size(); ++k)
          s.stages_ms[k].push_back(stages[k]);
    }
    return s;
  }

 private:
  const Options& o_;
  const bench::Source& source_;
  bench::FrameRate& frames_;
};

std::string fmt(double v, const char* f = "%.1f") {
  if (std::isnan(v)) return "–";
  char buf[32];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::vector<double> field(const std::vector<Sample>& v, double Sample::*f) {
  std::vector<double> out;
  for (const auto& s : v)
    if (!std::isnan(s.*f)) out.push_back(s.*f);
  return out;
}

// One line per case: each name's CPU (median over the rounds), names under 0.2 % left out.
void print_cpu_by_name(const std::vector<Case>& cases,
                       std::map<std::string, std::vector<Sample>>& results,
                       std::map<std::string, double> Sample::*by_name) {
  for (const auto& c : cases) {
    const auto& v = results[c.name];
    if (v.empty() || (v.front().*by_name).empty()) continue;
    std::string line;
    for (const auto& [name, cpu] : v.front().*by_name) {
      std::vector<double> per_round;
      for (const auto& smp : v) {
        const auto it = (smp.*by_name).find(name);
        if (it != (smp.*by_name).end()) per_round.push_back(it->second);
      }
      const double m = median(per_round);
      if (m > 0.2) line += (line.empty() ? "" : ", ") + name + " " + fmt(m);
    }
    std::printf("- %s: %s\n", c.name.c_str(), line.empty() ? "–" : line.c_str());
  }
}

int run_cases(const Options& o, const bench::Source& source, const std::string& log) {
  bench::FrameRate frames(o.domain, source.partition());
  std::vector<Case> cases = {{"no viewer", false, 0, false, ""}};
  // With a baseline, each round measures it case by case next to this build ("before:").
  std::vector<std::pair<std::string, std::string>> viewers = {
      {"", bench::sibling_program("stereoball-view")}};
  if (!o.baseline_viewer.empty()) viewers.insert(viewers.begin(), {"before: ", o.baseline_viewer});
  const sb::Status browser = o.browser ? bench::Browser::available() : sb::Status{};
  if (!browser.ok()) std::printf("(no Chromium case: %s)\n", browser.error().c_str());
  for (const auto& [prefix, program] : viewers) {
    for (int n : o.clients)
      cases.push_back(
          {prefix + std::to_string(n) + " client" + (n == 1 ? "" : "s"), true, n, false, program});
    if (o.browser && browser.ok()) cases.push_back({prefix + "1 Chromium", true, 0, true, program});
  }
  std::map<std::string, std::vector<Sample>> results;
  Measurer measurer(o, source, frames);
  const double load_start = bench::load_average();
  for (int round = 1; round <= o.repeats; ++round) {
    std::optional<Viewer> viewer;
    std::string running;  // the program of viewer
    for (const auto& c : cases) {
      if (viewer && c.program != running) viewer.reset();
      if (c.viewer && !viewer) {
        running = c.program;
        viewer = start_viewer(o, c.program, source.partition(), log);
        if (!viewer) {
          std::fprintf(stderr, "bench viewer: the viewer did not start (see %s-*.log)\n",
                       log.c_str());
          return 1;
        }
        std::this_thread::sleep_for(3s);  // discovery settles
      }
      const auto s = measurer.run(c, viewer ? &*viewer : nullptr);
      if (!s) continue;
      std::printf(
          "round %d, %-18s: viewer CPU %5s %%, robot CPU %5s %%, %5s frames/s, %5s pairs "
          "encoded/s, %5s images/s per client, latency p50 %5s ms, viewer RSS %5s MB\n",
          round, c.name.c_str(), fmt(s->viewer_cpu).c_str(), fmt(s->robot_cpu).c_str(),
          fmt(s->frames_hz).c_str(), fmt(s->encoded_per_s).c_str(),
          fmt(s->images_per_client_s).c_str(), fmt(percentile(s->latencies_ms, 0.5)).c_str(),
          fmt(s->rss_mb).c_str());
      std::fflush(stdout);
      results[c.name].push_back(*s);
    }
  }
  const double load_end = bench::load_average();
  std::printf(
      "\n%s, %.0f s per case, median of %d rounds; load average %.1f at start, %.1f at end "
      "(%ld cores)\n\n",
      source.describe().c_str(), o.phase_s, o.repeats, load_start, load_end,
      sysconf(_SC_NPROCESSORS_ONLN));
  std::printf(
      "| case | viewer CPU, %% of one core (runs) | robot CPU %% | frames/s | pairs made/s "
      "(encoded or preview) | "
      "images/s per client | capture→client p50 / p90 ms | viewer RSS MB |\n"
      "|---|---|---|---|---|---|---|---|\n");
  for (const auto& c : cases) {
    const auto& v = results[c.name];
    if (v.empty()) continue;
    std::string runs;
    for (double x : field(v, &Sample::viewer_cpu)) runs += (runs.empty() ? "" : ", ") + fmt(x);
    std::vector<double> lat;
    for (const auto& s : v) lat.insert(lat.end(), s.latencies_ms.begin(), s.latencies_ms.end());
    std::printf("| %s | %s%s | %s | %s | %s | %s | %s | %s |\n", c.name.c_str(),
                fmt(median(field(v, &Sample::viewer_cpu))).c_str(),
                runs.empty() ? "" : (" (" + runs + ")").c_str(),
                fmt(median(field(v, &Sample::robot_cpu))).c_str(),
                fmt(median(field(v, &Sample::frames_hz))).c_str(),
                fmt(median(field(v, &Sample::encoded_per_s))).c_str(),
                fmt(median(field(v, &Sample::images_per_client_s))).c_str(),
                lat.empty() ? "–"
                            : (fmt(percentile(lat, 0.5), "%.0f") + " / " +
                               fmt(percentile(lat, 0.9), "%.0f"))
                                  .c_str(),
                fmt(median(field(v, &Sample::rss_mb))).c_str());
  }
  std::printf(
      "\nthe viewer's CPU by thread, %% of one core (median of rounds; threads over 0.2)\n\n");
  print_cpu_by_name(cases, results, &Sample::viewer_threads_cpu);
  std::printf("\nthe robot's CPU by process, %% of one core (median of rounds; over 0.2)\n\n");
  print_cpu_by_name(cases, results, &Sample::robot_processes_cpu);
  std::printf("\nwhere the latency goes, p50 ms per stage (all rounds)\n\n| case |");
  for (const char* name : kStageNames) std::printf(" %s |", name);
  std::printf(" whole way p50 |\n|---|");
  for (size_t k = 0; k <= kStages; ++k) std::printf("---|");
  std::printf("\n");
  for (const auto& c : cases) {
    const auto& v = results[c.name];
    if (v.empty() || v.front().stages_ms[0].empty()) continue;
    std::printf("| %s |", c.name.c_str());
    std::vector<double> lat;
    for (size_t k = 0; k < kStages; ++k) {
      std::vector<double> all;
      for (const auto& smp : v)
        all.insert(all.end(), smp.stages_ms[k].begin(), smp.stages_ms[k].end());
      std::printf(" %s |", fmt(percentile(all, 0.5)).c_str());
    }
    for (const auto& smp : v)
      lat.insert(lat.end(), smp.latencies_ms.begin(), smp.latencies_ms.end());
    std::printf(" %s |\n", fmt(percentile(lat, 0.5)).c_str());
  }
  return 0;
}

// Least-squares slope of y over x.
double slope(const std::vector<std::pair<double, double>>& xy) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(xy.size());
  for (auto [x, y] : xy) {
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double d = n * sxx - sx * sx;
  return d > 0 ? (n * sxy - sx * sy) / d : NAN;
}

size_t open_fds(pid_t pid) {
  std::error_code ec;
  size_t n = 0;
  for (auto it = std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++n;
  return n;
}

int run_soak(const Options& o, const bench::Source& source, const std::string& log) {
  const auto viewer =
      start_viewer(o, bench::sibling_program("stereoball-view"), source.partition(), log);
  if (!viewer) {
    std::fprintf(stderr, "bench viewer: the viewer did not start (see %s-*.log)\n", log.c_str());
    return 1;
  }
  const int n = o.clients.empty() ? 10 : o.clients.front();
  const pid_t vp = viewer->child->pid();
  std::printf(
      "%s; %d clients (page and Foxglove alternately, each connected 0.5-2 s, every third "
      "dropped without a close frame) for %.0f s; load average %.1f\n",
      source.describe().c_str(), n, o.soak_s, bench::load_average());
  std::atomic<bool> stop{false};
  std::atomic<uint64_t> sessions{0}, failed{0};
  std::vector<std::thread> threads;
  for (int i = 0; i < n; ++i) {
    threads.emplace_back([&, i] {
      for (uint64_t round = 0; !stop; ++round) {
        const auto kind =
            (round + i) % 2 ? vc::WsClient::Kind::kFoxglove : vc::WsClient::Kind::kPage;
        {
          vc::WsClient client(viewer->port, kind);
          if (!client.connected()) ++failed;
          client.set_clean_close(round % 3 != 0);
          const int hold_ms = 500 + static_cast<int>((round * 7919 + i * 104729) % 1500);
          for (int t = 0; t < hold_ms && !stop; t += 50) std::this_thread::sleep_for(50ms);
        }
        ++sessions;
        std::this_thread::sleep_for(100ms);
      }
    });
  }
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::pair<double, double>> rss;  // (minutes, MB)
  const size_t fds0 = open_fds(vp);
  double next_print_min = 0;
  for (;;) {
    const double min =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 60;
    const auto r = bench::rss_mb(vp);
    if (!r) {
      std::printf("the viewer exited during the soak (see %s-1.log)\n", log.c_str());
      stop = true;
      for (auto& t : threads) t.join();
      return 1;
    }
    rss.emplace_back(min, *r);
    if (min >= next_print_min) {
      std::printf("  %5.1f min: viewer RSS %6.1f MB, %llu sessions, %zu open fds, load %.1f\n", min,
                  *r, static_cast<unsigned long long>(sessions.load()), open_fds(vp),
                  bench::load_average());
      std::fflush(stdout);
      next_print_min += 1;
    }
    if (min * 60 >= o.soak_s) break;
    std::this_thread::sleep_for(1s);
  }
  stop = true;
  for (auto& t : threads) t.join();
  std::this_thread::sleep_for(2s);  // the last closes reach the viewer
  const double end_mb = bench::rss_mb(vp).value_or(NAN);
  std::vector<std::pair<double, double>> after_first;
  for (const auto& p : rss)
    if (p.first >= 1) after_first.push_back(p);
  std::printf(
      "  end: viewer RSS %.1f MB (start %.1f, max %.1f), %llu sessions (%llu refused), viewer "
      "counted %ld connections, %ld clients connected now, open fds %zu -> %zu\n"
      "  RSS slope %.3f MB/min over the whole run, %.3f MB/min after the first minute\n",
      end_mb, rss.front().second,
      std::max_element(rss.begin(), rss.end(), [](auto& a, auto& b) { return a.second < b.second; })
          ->second,
      static_cast<unsigned long long>(sessions.load()),
      static_cast<unsigned long long>(failed.load()), stats_counter(viewer->port, "connections"),
      stats_counter(viewer->port, "browsers") + stats_counter(viewer->port, "foxglove_clients"),
      fds0, open_fds(vp), slope(rss), after_first.size() > 2 ? slope(after_first) : NAN);
  return 0;
}

// A viewer with --clients page-like clients on another program's partition (e.g. `stereoball
// bench latency` measured with and without someone watching) for --watch-s seconds.
int run_watch(const Options& o, const std::string& log) {
  const auto viewer =
      start_viewer(o, bench::sibling_program("stereoball-view"), o.watch_partition, log);
  if (!viewer) {
    std::fprintf(stderr, "bench viewer: the viewer did not start (see %s-*.log)\n", log.c_str());
    return 1;
  }
  const int n = o.clients.empty() ? 1 : o.clients.front();
  std::vector<std::unique_ptr<vc::WsClient>> clients;
  for (int i = 0; i < n; ++i)
    clients.push_back(std::make_unique<vc::WsClient>(viewer->port, vc::WsClient::Kind::kPage));
  const pid_t vp = viewer->child->pid();
  const double cpu0 = bench::cpu_seconds(vp).value_or(NAN);
  const auto t0 = std::chrono::steady_clock::now();
  std::this_thread::sleep_for(std::chrono::duration<double>(o.watch_s));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  uint64_t images = 0;
  for (const auto& c : clients) images += c->images();
  std::printf(
      "watched partition %s with %d client(s) for %.0f s: %.1f images/s per client, "
      "viewer CPU %.1f %% of one core, %ld pairs from previews, %ld encoded\n",
      o.watch_partition.c_str(), n, wall, images / wall / n,
      (bench::cpu_seconds(vp).value_or(NAN) - cpu0) / wall * 100,
      stats_counter(viewer->port, "pairs_from_preview"),
      stats_counter(viewer->port, "pairs_encoded"));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"stereoball bench viewer: CPU, latency and memory of stereoball view"};
  Options o;
  app.add_option("--source", o.source, "what the viewer watches: demo or synthetic")
      ->check(CLI::IsMember({"demo", "synthetic"}))
      ->capture_default_str();
  app.add_option("--scenario", o.scenario, "demo scenario")->capture_default_str();
  app.add_option("--width", o.width, "synthetic image width")->check(CLI::Range(16, 4096));
  app.add_option("--height", o.height, "synthetic image height")->check(CLI::Range(16, 4096));
  app.add_flag("--jpeg", o.jpeg, "synthetic frames JPEG-compressed, as from JPEG cameras");
  app.add_option("--rate", o.rate_hz, "synthetic frames per second")->check(CLI::Range(1.0, 240.0));
  app.add_option("--phase-s", o.phase_s, "seconds per measurement")
      ->check(CLI::Range(1.0, 600.0))
      ->capture_default_str();
  app.add_option("--repeats", o.repeats, "rounds (the figures are medians)")
      ->check(CLI::Range(1, 20))
      ->capture_default_str();
  app.add_option("--clients", o.clients,
                 "client counts measured (default 0 1 2 5); with --soak, clients in the loop "
                 "(default 10)")
      ->check(CLI::Range(0, 100));
  app.add_flag("!--no-browser", o.browser, "skip the headless Chromium case");
  app.add_option("--soak", o.soak_s, "seconds of clients connecting and disconnecting instead")
      ->check(CLI::Range(10.0, 86400.0));
  app.add_option("--watch", o.watch_partition,
                 "no source: a viewer (and --clients page clients, default 1) on this partition "
                 "for --watch-s seconds (wildcards work)");
  app.add_option("--watch-s", o.watch_s, "seconds of --watch")->check(CLI::Range(1.0, 86400.0));
  app.add_option("--viewer-arg", o.viewer_args, "extra argument for stereoball view (repeatable)")
      ->allow_extra_args(false);
  app.add_option("--baseline-viewer", o.baseline_viewer,
                 "another stereoball-view build measured in the same rounds (cases 'before: ...')")
      ->check(CLI::ExistingFile);
  app.add_option("--domain", o.domain)->check(CLI::Range(0, 232))->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (o.clients.empty() && o.soak_s == 0) o.clients = {0, 1, 2, 5};
  const std::string work = "/tmp/stereoball-bench-viewer-" + std::to_string(getpid());
  std::filesystem::create_directories(work);
  const std::string log = work + "/viewer";
  // The demo and the viewer use the single-host DDS configuration, as `stereoball demo` does.
  if (!std::getenv("CYCLONEDDS_URI")) {
    const auto xml = sb::paths::shipped_config_path("cyclonedds/loopback.xml");
    if (std::filesystem::exists(xml))
      setenv("CYCLONEDDS_URI", ("file://" + std::filesystem::absolute(xml).string()).c_str(), 1);
  }
  if (!o.watch_partition.empty()) return run_watch(o, log);
  std::unique_ptr<bench::Source> source;
  if (o.source == "demo") {
    std::string error;
    source = bench::start_demo(o.domain, o.scenario, work, error);
    if (!source) {
      std::fprintf(stderr, "bench viewer: %s\n", error.c_str());
      return 1;
    }
  } else {
    source = bench::start_synthetic(o.domain, o.width, o.height, o.rate_hz, o.jpeg);
  }
  std::printf("logs in %s\n", work.c_str());
  return o.soak_s > 0 ? run_soak(o, *source, log) : run_cases(o, *source, log);
}
