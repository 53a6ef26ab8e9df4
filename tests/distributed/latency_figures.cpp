#include "latency_figures.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "two_host_system.hpp"

namespace stereoball::distributed {
namespace {

double ms(std::int64_t ns) {
  return static_cast<double>(ns) / 1e6;
}

template <typename T>
std::map<std::int64_t, const T*> by_capture(const std::vector<T>& samples, std::int64_t from_ns,
                                            std::int64_t to_ns) {
  std::map<std::int64_t, const T*> out;
  for (const auto& s : samples) {
    if (s.capture_ns >= from_ns && s.capture_ns < to_ns) out.emplace(s.capture_ns, &s);
  }
  return out;
}

// Frames missing between consecutive detections: a gap of k periods hides k - 1 frames.
void count_frames(const std::map<std::int64_t, const DetectionRx*>& detections,
                  double frame_rate_hz, LatencyFigures& f) {
  if (detections.empty()) return;
  const double period_ns = 1e9 / frame_rate_hz;
  const auto span = static_cast<double>(detections.rbegin()->first - detections.begin()->first);
  f.frames_expected = static_cast<std::size_t>(std::llround(span / period_ns)) + 1;
  f.frames_lost = f.frames_expected - std::min(f.frames_expected, detections.size());
}

std::vector<int> children_of(int pid) {
  std::vector<int> out;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.empty() || !std::all_of(name.begin(), name.end(), ::isdigit)) continue;
    std::ifstream in(e.path() / "stat");
    std::string text((std::istreambuf_iterator<char>(in)), {});
    const auto paren = text.rfind(')');
    if (paren == std::string::npos) continue;
    std::istringstream rest(text.substr(paren + 2));
    std::string state;
    int ppid = 0;
    if (rest >> state >> ppid && ppid == pid) out.push_back(std::stoi(name));
  }
  return out;
}

unsigned long long process_ticks(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto paren = text.rfind(')');
  if (paren == std::string::npos) return 0;
  std::istringstream rest(text.substr(paren + 2));
  std::string field;
  unsigned long long utime = 0, stime = 0;
  for (int i = 3; i <= 13 && rest >> field; ++i) {
  }
  rest >> utime >> stime;  // fields 14 and 15
  return utime + stime;
}

std::set<int> with_descendants(const std::vector<int>& pids) {
  std::set<int> all;
  std::vector<int> todo = pids;
  while (!todo.empty()) {
    const int pid = todo.back();
    todo.pop_back();
    if (!all.insert(pid).second) continue;
    for (int child : children_of(pid)) todo.push_back(child);
  }
  return all;
}

// The file name of a process's argv[0] ("" when it is gone).
std::string program_name(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/cmdline");
  std::string argv0;
  std::getline(in, argv0, '\0');
  return std::filesystem::path(argv0).filename().string();
}

nlohmann::json quantiles_json(const Quantiles& q) {
  return {{"p50", q.p50}, {"p90", q.p90}, {"p99", q.p99}, {"max", q.max}, {"n", q.n}};
}

}  // namespace

Quantiles quantiles(const std::vector<double>& values_ms) {
  Quantiles q;
  q.n = values_ms.size();
  if (values_ms.empty()) return q;
  q.p50 = percentile(values_ms, 50);
  q.p90 = percentile(values_ms, 90);
  q.p99 = percentile(values_ms, 99);
  q.max = percentile(values_ms, 100);
  return q;
}

std::vector<FrameStages> frame_stages(const ObserverLog& detection_log,
                                      const ObserverLog& control_log, std::int64_t from_ns,
                                      std::int64_t to_ns) {
  const auto detections = by_capture(detection_log.detections, from_ns, to_ns);
  const auto tracks = by_capture(control_log.tracks, from_ns, to_ns);
  std::map<std::int64_t, const CommandRx*> commands;
  for (const auto& c : control_log.commands) {
    if (c.capture_ns != 0) commands.emplace(c.capture_ns, &c);
  }
  std::vector<FrameStages> out;
  for (const auto& [capture, d] : detections) {
    FrameStages f;
    f.capture_ns = capture;
    f.seq = d->frame_seq;
    f.detection_status = d->status;
    f.received_ms = ms(d->publish_ns - capture) - d->processing_ms;
    f.detection_ms = d->processing_ms;
    const auto t = tracks.find(capture);
    if (t != tracks.end()) {
      f.track_state = t->second->state;
      f.track_ms = ms(t->second->publish_ns - d->publish_ns);
      const auto c = commands.find(capture);
      if (c != commands.end()) {
        f.command_ms = ms(c->second->stamp_ns - t->second->publish_ns);
        f.end_to_end_ms = ms(c->second->stamp_ns - capture);
      }
    }
    out.push_back(f);
  }
  return out;
}

LatencyFigures latency_figures(const ObserverLog& detection_log, const ObserverLog& control_log,
                               std::int64_t from_ns, std::int64_t to_ns, double frame_rate_hz) {
  const auto frames = frame_stages(detection_log, control_log, from_ns, to_ns);
  std::vector<double> received, detection, track, command, end_to_end;
  LatencyFigures f;
  for (const FrameStages& s : frames) {
    received.push_back(s.received_ms);
    detection.push_back(s.detection_ms);
    if (s.track_state < 0) continue;
    track.push_back(s.track_ms);
    if (s.end_to_end_ms < 0) {
      ++f.tracks_unanswered;
      continue;
    }
    command.push_back(s.command_ms);
    end_to_end.push_back(s.end_to_end_ms);
  }
  f.frame_received = quantiles(received);
  f.detection = quantiles(detection);
  f.track = quantiles(track);
  f.command = quantiles(command);
  f.end_to_end = quantiles(end_to_end);
  count_frames(by_capture(detection_log.detections, from_ns, to_ns), frame_rate_hz, f);
  return f;
}

std::string to_csv(const std::vector<FrameStages>& frames, std::int64_t measured_from_ns) {
  std::string out =
      "capture_ns,seq,detection_status,track_state,received_ms,detection_ms,track_ms,command_ms,"
      "end_to_end_ms,measured\n";
  char line[256];
  for (const FrameStages& f : frames) {
    std::snprintf(line, sizeof line, "%lld,%llu,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%d\n",
                  static_cast<long long>(f.capture_ns), static_cast<unsigned long long>(f.seq),
                  f.detection_status, f.track_state, f.received_ms, f.detection_ms, f.track_ms,
                  f.command_ms, f.end_to_end_ms, f.capture_ns >= measured_from_ns ? 1 : 0);
    out += line;
  }
  return out;
}

SlowFrames slowest_frames(const std::vector<FrameStages>& frames, std::int64_t from_ns,
                          double share_pct) {
  std::vector<const FrameStages*> answered;
  std::vector<double> end_to_end;
  for (const FrameStages& f : frames) {
    if (f.capture_ns < from_ns || f.end_to_end_ms < 0) continue;
    answered.push_back(&f);
    end_to_end.push_back(f.end_to_end_ms);
  }
  SlowFrames s;
  if (answered.empty()) return s;
  const double from_ms = percentile(end_to_end, 100.0 - share_pct);
  for (const FrameStages* f : answered) {
    if (f->end_to_end_ms < from_ms) continue;
    ++s.n;
    s.not_found += f->detection_status != 0 ? 1 : 0;
    s.received_ms += f->received_ms;
    s.detection_ms += f->detection_ms;
    s.track_ms += f->track_ms;
    s.command_ms += f->command_ms;
    s.end_to_end_ms += f->end_to_end_ms;
  }
  const double n = static_cast<double>(s.n);
  for (double* v : {&s.received_ms, &s.detection_ms, &s.track_ms, &s.command_ms, &s.end_to_end_ms})
    *v /= n;
  return s;
}

std::string to_text(const SlowFrames& s, double share_pct) {
  char line[240];
  std::snprintf(line, sizeof line,
                "  slowest %.0f%% end to end: %zu frames, %zu without a ball found; mean ms: "
                "received %.2f, detection %.2f, track %.2f, command %.2f, end to end %.2f\n",
                share_pct, s.n, s.not_found, s.received_ms, s.detection_ms, s.track_ms,
                s.command_ms, s.end_to_end_ms);
  return line;
}

nlohmann::json to_json(const SlowFrames& s) {
  return {{"n", s.n},
          {"not_found", s.not_found},
          {"received_ms", s.received_ms},
          {"detection_ms", s.detection_ms},
          {"track_ms", s.track_ms},
          {"command_ms", s.command_ms},
          {"end_to_end_ms", s.end_to_end_ms}};
}

CpuSample cpu_sample(const std::vector<int>& pids) {
  CpuSample s;
  s.wall_ns = static_cast<std::int64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                            std::chrono::steady_clock::now().time_since_epoch())
                                            .count());
  std::ifstream stat("/proc/stat");
  std::string cpu;
  unsigned long long v[8] = {};
  if (stat >> cpu && cpu == "cpu") {
    for (auto& x : v) stat >> x;
    // user nice system idle iowait irq softirq steal
    s.host_total_ticks = v[0] + v[1] + v[2] + v[3] + v[4] + v[5] + v[6] + v[7];
    s.host_busy_ticks = s.host_total_ticks - v[3] - v[4];
  }
  for (int pid : with_descendants(pids)) s.process_ticks += process_ticks(pid);
  return s;
}

CoreLoad core_load(const CpuSample& start, const CpuSample& end) {
  CoreLoad l;
  l.cores = static_cast<int>(sysconf(_SC_NPROCESSORS_ONLN));
  std::ifstream in("/proc/loadavg");
  in >> l.load_average_1m;
  const double total = static_cast<double>(end.host_total_ticks - start.host_total_ticks);
  if (total > 0) {
    l.host_busy_pct =
        100.0 * static_cast<double>(end.host_busy_ticks - start.host_busy_ticks) / total;
  }
  const double wall_s = static_cast<double>(end.wall_ns - start.wall_ns) * 1e-9;
  const double ticks_per_s = static_cast<double>(sysconf(_SC_CLK_TCK));
  if (wall_s > 0 && end.process_ticks >= start.process_ticks) {
    l.our_processes_pct =
        100.0 * static_cast<double>(end.process_ticks - start.process_ticks) / ticks_per_s / wall_s;
  }
  return l;
}

nlohmann::json to_json(const LatencyFigures& f, const CoreLoad& load) {
  return {{"frame_received_ms", quantiles_json(f.frame_received)},
          {"detection_ms", quantiles_json(f.detection)},
          {"track_ms", quantiles_json(f.track)},
          {"command_ms", quantiles_json(f.command)},
          {"end_to_end_ms", quantiles_json(f.end_to_end)},
          {"frames_expected", f.frames_expected},
          {"frames_lost", f.frames_lost},
          {"tracks_unanswered", f.tracks_unanswered},
          {"load",
           {{"cores", load.cores},
            {"load_average_1m", load.load_average_1m},
            {"host_busy_pct", load.host_busy_pct},
            {"our_processes_pct_of_one_core", load.our_processes_pct}}}};
}

std::string to_text(const std::string& title, const LatencyFigures& f, const CoreLoad& load) {
  std::string out = title + "\n";
  char line[200];
  const std::pair<const char*, const Quantiles*> rows[] = {
      {"capture -> frame received", &f.frame_received},
      {"detection", &f.detection},
      {"track", &f.track},
      {"command", &f.command},
      {"end to end (capture -> command)", &f.end_to_end}};
  for (const auto& [name, q] : rows) {
    std::snprintf(line, sizeof line,
                  "  %-33s n=%-5zu p50 %6.2f  p90 %6.2f  p99 %6.2f  max %6.2f ms\n", name, q->n,
                  q->p50, q->p90, q->p99, q->max);
    out += line;
  }
  std::snprintf(line, sizeof line,
                "  frames lost %zu of %zu, tracks without a command %zu; load: %d cores %.0f%% "
                "busy (everyone), ours %.0f%% of one core, load average %.2f\n",
                f.frames_lost, f.frames_expected, f.tracks_unanswered, load.cores,
                load.host_busy_pct, load.our_processes_pct, load.load_average_1m);
  out += line;
  return out;
}

}  // namespace stereoball::distributed

namespace stereoball::distributed {

ProgramSample program_sample(const std::vector<int>& pids) {
  ProgramSample out;
  for (int pid : with_descendants(pids)) {
    const std::string name = program_name(pid);
    if (name.empty()) continue;
    ProgramCounters& p = out[name];
    p.ticks += process_ticks(pid);
    std::error_code ec;
    const std::string tasks = "/proc/" + std::to_string(pid) + "/task";
    for (const auto& e : std::filesystem::directory_iterator(tasks, ec)) {
      std::ifstream in(e.path() / "schedstat");
      ThreadTimes t;
      if (!(in >> t.run_ns >> t.wait_ns)) continue;
      p.threads[{pid, std::atoi(e.path().filename().c_str())}] = t;
    }
  }
  return out;
}

std::map<std::string, ProgramCpu> program_cpu(const ProgramSample& start, const ProgramSample& end,
                                              double frames) {
  std::map<std::string, ProgramCpu> out;
  if (frames <= 0) return out;
  const double ms_per_tick = 1e3 / static_cast<double>(sysconf(_SC_CLK_TCK));
  for (const auto& [name, e] : end) {
    const auto s = start.find(name);
    // Threads alive at the end: their change since the start, or all of it if they started
    // later. Threads that ended in between are missing here (the simulator starts one per
    // frame), but not from the ticks, which count every thread of a process.
    std::int64_t run_ns = 0, wait_ns = 0;
    for (const auto& [id, t] : e.threads) {
      ThreadTimes before;
      if (s != start.end()) {
        if (const auto b = s->second.threads.find(id); b != s->second.threads.end())
          before = b->second;
      }
      run_ns += t.run_ns - before.run_ns;
      wait_ns += t.wait_ns - before.wait_ns;
    }
    const unsigned long long ticks_before = s == start.end() ? 0 : s->second.ticks;
    const double tick_ms =
        e.ticks >= ticks_before ? static_cast<double>(e.ticks - ticks_before) * ms_per_tick : 0;
    // Nanosecond counters where they see every thread; the ticks (10 ms steps) otherwise.
    const double cpu_ms = std::max(static_cast<double>(run_ns) * 1e-6, tick_ms);
    out[name] = ProgramCpu{cpu_ms / frames, static_cast<double>(wait_ns) * 1e-6 / frames};
  }
  return out;
}

std::string program_cpu_text(const std::map<std::string, ProgramCpu>& cpu) {
  std::string out = "  per frame, CPU ms (run-queue wait ms):";
  char part[120];
  for (const auto& [name, c] : cpu) {
    std::snprintf(part, sizeof part, " %s %.2f (%.2f)", name.c_str(), c.cpu_ms, c.runqueue_ms);
    out += part;
  }
  return out + "\n";
}

nlohmann::json program_cpu_json(const std::map<std::string, ProgramCpu>& cpu) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [name, c] : cpu)
    out[name] = {{"cpu_ms", c.cpu_ms}, {"runqueue_wait_ms", c.runqueue_ms}};
  return out;
}

}  // namespace stereoball::distributed
