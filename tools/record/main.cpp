// stereoball record [-o FILE] [--all | TOPIC...] [--exclude T] [--split-size MB]
//                   [--split-duration S]
// Takes samples of the chosen topics as serialized CDR (exactly as they travelled) and writes
// them to MCAP off the DDS thread through a bounded queue. Prints live progress once a second;
// Ctrl-C (SIGINT/SIGTERM) stops it with a complete file.

#include "common/util/cli11.hpp"
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include <cstdio>
#include <ctime>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "recorder/core/selection.hpp"
#include "recorder/io/recording.hpp"
#include "recorder/node/recorder_node.hpp"
#include "stereoball/idl_text.hpp"
#include "stereoball/topics.hpp"
#include "viewer/recording/derived_recording.hpp"

namespace sb = stereoball;
namespace rec = stereoball::recorder;

namespace {

struct Options {
  std::string output;
  bool all = false;
  std::vector<std::string> topics;
  std::vector<std::string> exclude;
  double split_size_mb = 0;
  double split_duration_s = 0;
  double duration_s = 0;
  double queue_mb = 256;
  double chunk_mb = 4;
  double flush_period_s = 1.0;
  std::string compression = "zstd";
  int zstd_level = 1;
  bool quiet = false;
  bool derived = false;
  bool no_derived = false;
  double derived_image_hz = 10;
};

std::string default_output() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char name[64];
  std::strftime(name, sizeof name, "stereoball_%Y%m%d_%H%M%S.mcap", &tm);
  return name;
}

void print_progress(double elapsed_s, const std::vector<std::string>& names,
                    const std::vector<rec::TopicCounters>& c, const std::vector<uint64_t>& lost,
                    uint64_t queued) {
  std::string line;
  char buf[160];
  for (size_t i = 0; i < names.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%s %llu msg %.1f MB drop %llu lost %llu", i ? " | " : "",
                  names[i].c_str(), static_cast<unsigned long long>(c[i].messages),
                  c[i].bytes / 1e6, static_cast<unsigned long long>(c[i].dropped),
                  static_cast<unsigned long long>(lost[i]));
    line += buf;
  }
  std::fprintf(stderr, "[%6.1f s] %s | queue %.1f MB\n", elapsed_s, line.c_str(), queued / 1e6);
}

}  // namespace

int main(int argc, char** argv) {
#ifdef __GLIBC__
  // glibc raises its mmap threshold each time a mapped block is freed (up to 32 MiB), after
  // which large buffers whose size follows the data (zstd's workspace, Cyclone's receive
  // buffers) come from the per-thread arenas, and the holes they leave are never returned: in
  // a 30-minute chaos run the recorder's resident memory rose in steps of 300-400 kB at the
  // bursts while its live heap stayed flat (tools/bench-chaos/README.md). A fixed threshold
  // (glibc's own default) keeps every block of 128 KiB or more in its own mapping, handed
  // back to the system when freed.
  mallopt(M_MMAP_THRESHOLD, 128 * 1024);
#endif
  sb::node::block_termination_signals();
  CLI::App app{
      "stereoball record: record topics to an MCAP file (zstd chunks, indexes, summary). "
      "Samples are stored as the CDR bytes that travelled (message encoding cdr) with the IDL "
      "as omgidl schema; log time = receive time, publish time = source timestamp. Stop with "
      "Ctrl-C; a killed recorder leaves a file readable up to its last chunk."};
  Options o;
  sb::node::CommonOptions common;
  std::vector<std::string> known;
  for (const auto& t : sb::topics::all()) known.emplace_back(t.name);
  app.add_option("TOPIC", o.topics, "topics to record (see `stereoball topic list`)");
  app.add_flag("-a,--all", o.all, "record every topic of the topic table");
  app.add_option("-x,--exclude", o.exclude, "topic to leave out (repeatable)");
  app.add_option("-o,--output", o.output, "output file (default stereoball_<UTC time>.mcap)");
  app.add_option("--split-size", o.split_size_mb, "start a new file after this many MB (0 = off)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--split-duration", o.split_duration_s,
                 "start a new file after this many seconds (0 = off)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--duration", o.duration_s, "stop after this many seconds (0 = until Ctrl-C)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--queue-mb", o.queue_mb, "memory for queued samples before dropping, MB")
      ->capture_default_str();
  app.add_option("--chunk-mb", o.chunk_mb, "target uncompressed chunk size, MB")
      ->capture_default_str();
  app.add_option("--flush-period", o.flush_period_s,
                 "write out a partly filled chunk after this many seconds (crash safety)")
      ->capture_default_str();
  app.add_option("--compression", o.compression, "chunk compression")
      ->check(CLI::IsMember({"zstd", "none"}))
      ->capture_default_str();
  app.add_option("--zstd-level", o.zstd_level, "zstd level 1..19")->capture_default_str();
  app.add_flag("-q,--quiet", o.quiet, "no live progress");
  app.add_flag("--derived", o.derived,
               "also record the derived Foxglove channels (view/*: images with detections drawn, "
               "3D scene); on by default with --all");
  app.add_flag("--no-derived", o.no_derived, "do not record the derived channels");
  app.add_option("--derived-image-hz", o.derived_image_hz,
                 "images per second in the derived image channels")
      ->check(CLI::Range(0.1, 120.0))
      ->capture_default_str();
  sb::node::add_common_flags(app, common, "", false);
  CLI11_PARSE(app, argc, argv);

  auto selected = rec::select_topics(known, o.topics, o.all, o.exclude);
  if (!selected) {
    std::fprintf(stderr, "stereoball record: %s\n", selected.error().c_str());
    return 2;
  }
  rec::RecordingParams params;
  params.path = o.output.empty() ? default_output() : o.output;
  params.split_size_bytes = static_cast<uint64_t>(o.split_size_mb * 1e6);
  params.split_duration_ns = static_cast<int64_t>(o.split_duration_s * 1e9);
  params.queue_limit_bytes = static_cast<uint64_t>(o.queue_mb * 1e6);
  params.chunk_flush_period_ns = static_cast<int64_t>(o.flush_period_s * 1e9);
  params.writer.chunk_size_bytes = static_cast<uint64_t>(o.chunk_mb * (1 << 20));
  params.writer.compression =
      o.compression == "zstd" ? rec::Compression::kZstd : rec::Compression::kNone;
  params.writer.zstd_level = o.zstd_level;
  if (auto bad = params.validate(); !bad) {
    std::fprintf(stderr, "stereoball record: %s\n", bad.error().c_str());
    return 2;
  }
  std::vector<rec::RecordedTopic> topics;
  std::vector<const sb::topics::TopicSpec*> specs;
  for (const auto& name : *selected) {
    const auto* spec = sb::topics::find(name);
    specs.push_back(spec);
    topics.push_back({name, std::string(spec->type_name), std::string(sb::idl_text())});
  }
  const bool derived = (o.all || o.derived) && !o.no_derived;
  sb::viewer::DeriverParams derive;
  derive.image_rate_hz = o.derived_image_hz;
  if (derived) {
    for (auto& t : sb::viewer::derived_recorded_topics()) {
      selected->push_back(t.topic);
      topics.push_back(std::move(t));
    }
  }

  try {
    sb::node::Runner runner("recorder", common);
    auto recording = rec::Recording::start(params, topics);
    if (!recording) {
      std::fprintf(stderr, "stereoball record: %s\n", recording.error().c_str());
      return 1;
    }
    std::printf("recording %zu topic(s) to %s (domain %d%s%s):\n", specs.size(),
                params.path.c_str(), common.domain_id,
                common.partition.empty() ? "" : ", partition ", common.partition.c_str());
    for (const auto* spec : specs) {
      std::printf("  %-20.*s %.*s\n", static_cast<int>(spec->name.size()), spec->name.data(),
                  static_cast<int>(spec->type_name.size()), spec->type_name.data());
    }
    if (derived) std::printf("  view/* (derived: images, detections, 3D scene for Foxglove)\n");
    rec::RecorderNode node(runner, sb::dds::ParticipantOptions{common.domain_id, common.partition},
                           specs, **recording, derived ? std::optional(derive) : std::nullopt);
    std::fflush(stdout);
    const int64_t start = sb::node::monotonic_ns();
    bool failed = false;
    // Samples DDS lost before we could take them are reported beside the queue drops so no
    // loss is silent.
    runner.every(1'000'000'000, [&](int64_t) {
      node.update_lost();
      if (!o.quiet) {
        print_progress((sb::node::monotonic_ns() - start) / 1e9, *selected,
                       (*recording)->counters(), node.lost(), (*recording)->queued_bytes());
      }
      if (auto st = (*recording)->status(); !st) {
        std::fprintf(stderr, "stereoball record: write failed, stopping: %s\n", st.error().c_str());
        failed = true;
        runner.stop();
      }
    });
    if (o.duration_s > 0) {
      runner.every(static_cast<int64_t>(o.duration_s * 1e9), [&](int64_t) { runner.stop(); });
    }
    runner.run();
    node.update_lost();
    node.stop();
    const auto stopped = (*recording)->stop();
    const auto counters = (*recording)->counters();
    uint64_t total = 0, dropped = 0, lost_total = 0;
    for (const auto& c : counters) {
      total += c.messages;
      dropped += c.dropped;
    }
    for (uint64_t l : node.lost()) lost_total += l;
    std::printf("stopped: %llu messages written, %llu dropped, %llu lost in DDS, file(s):",
                static_cast<unsigned long long>(total), static_cast<unsigned long long>(dropped),
                static_cast<unsigned long long>(lost_total));
    for (const auto& f : (*recording)->files()) std::printf(" %s", f.c_str());
    std::printf("\n");
    if (!stopped.ok() || failed) {
      std::fprintf(stderr, "stereoball record: %s (file readable up to its last chunk)\n",
                   !stopped.ok() ? stopped.error().c_str() : "write failed");
      return 1;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "stereoball record: %s\n", e.what());
    return 1;
  }
}
