// stereoball play FILE [--rate X] [--loop] [--topics ...] [--start-offset S]
// Publishes a recording's samples unchanged (serialized CDR) with the original inter-message
// timing scaled by --rate, on the topic table's QoS (so calibration is transient-local).
// Works on incomplete files (linear scan up to the last complete chunk).

#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "common/dds/serialized.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"
#include "recorder/core/reader.hpp"
#include "recorder/core/selection.hpp"
#include "recorder/io/file_io.hpp"
#include "stereoball/topics.hpp"
#include "viewer/core/foxglove_schemas.hpp"

namespace sb = stereoball;
namespace rec = stereoball::recorder;

namespace {

// Sleeps until the monotonic time due_ns; false when a stop was requested meanwhile.
bool sleep_until(int64_t due_ns, const sb::node::Runner& runner) {
  constexpr int64_t kSlice = 50'000'000;  // re-check for Ctrl-C at least this often
  while (!runner.stopping()) {
    const int64_t left = due_ns - sb::node::monotonic_ns();
    if (left <= 0) return true;
    std::this_thread::sleep_for(std::chrono::nanoseconds(std::min(left, kSlice)));
  }
  return false;
}

int fail(const std::string& what) {
  std::fprintf(stderr, "stereoball play: %s\n", what.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  sb::node::block_termination_signals();
  CLI::App app{
      "stereoball play: publish a recording made by `stereoball record` with the original "
      "timing (scaled by --rate), using the topic table's QoS. Incomplete files are played up "
      "to their last complete chunk."};
  std::string path;
  rec::PlaybackParams params;
  std::vector<std::string> only;
  double wait_s = 1.0;
  sb::node::CommonOptions common;
  app.add_option("FILE", path, "MCAP file")->required();
  app.add_option("-r,--rate", params.rate, "time scale (2 = twice as fast)")->capture_default_str();
  app.add_flag("-l,--loop", params.loop, "start over at the end until Ctrl-C");
  app.add_option("-t,--topics", only, "play only these topics (default: all in the file)");
  app.add_option("-s,--start-offset", params.start_offset_s,
                 "skip this many seconds from the start of the recording")
      ->capture_default_str();
  app.add_option("--wait", wait_s, "seconds to wait for subscribers to be discovered first")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  sb::node::add_common_flags(app, common, "", false);
  CLI11_PARSE(app, argc, argv);
  if (auto bad = params.validate(); !bad) return fail(bad.error());

  auto source = rec::FileSource::open(path);
  if (!source) return fail(source.error());
  rec::McapReader reader(**source);
  if (auto err = reader.open(); !err) return fail(path + ": " + err.error());
  for (const auto& n : reader.notes())
    std::fprintf(stderr, "stereoball play: note: %s\n", n.c_str());

  const auto& summary = reader.summary();
  for (const auto& t : only) {
    bool present = false;
    for (const auto& [id, c] : summary.channels) present |= c.topic == t;
    if (!present) return fail("topic '" + t + "' is not in " + path);
  }
  try {
    sb::node::Runner runner("player", common);
    std::map<uint16_t, std::unique_ptr<sb::dds::SerializedWriter>> writers;
    std::map<uint16_t, uint64_t> published;
    for (const auto& [id, channel] : summary.channels) {
      if (!only.empty() && std::find(only.begin(), only.end(), channel.topic) == only.end())
        continue;
      const auto* spec = sb::topics::find(channel.topic);
      const auto schema = summary.schemas.find(channel.schema_id);
      if (schema != summary.schemas.end() &&
          sb::viewer::foxglove::is_foxglove_schema(schema->second.name)) {
        // Derived for people to watch (stereoball record --derived): never fed back to nodes.
        std::printf("ignoring %s (derived %s channel)\n", channel.topic.c_str(),
                    schema->second.name.c_str());
        continue;
      }
      if (spec == nullptr || channel.message_encoding != "cdr") {
        std::fprintf(stderr, "stereoball play: skipping '%s' (not a topic of the table)\n",
                     channel.topic.c_str());
        continue;
      }
      writers[id] = std::make_unique<sb::dds::SerializedWriter>(runner.participant(), *spec);
      std::printf("playing %s\n", channel.topic.c_str());
    }
    if (writers.empty()) return fail("nothing to play in " + path);
    std::fflush(stdout);
    if (!sleep_until(sb::node::monotonic_ns() + static_cast<int64_t>(wait_s * 1e9), runner))
      return 0;

    const uint64_t skip_before = summary.statistics.message_start_time_ns +
                                 static_cast<uint64_t>(params.start_offset_s * 1e9);
    do {
      std::optional<rec::PlaybackSchedule> schedule;
      auto err = reader.for_each_message([&](const rec::MessageView& m) {
        const auto w = writers.find(m.channel_id);
        if (w == writers.end() || m.log_time_ns < skip_before) return true;
        if (!schedule) schedule.emplace(m.log_time_ns, sb::node::monotonic_ns(), params.rate);
        if (!sleep_until(schedule->due_ns(m.log_time_ns), runner)) return false;
        w->second->write(m.data);
        ++published[m.channel_id];
        return true;
      });
      if (!err.ok()) return fail(err.error());
    } while (params.loop && !runner.stopping());

    uint64_t total = 0;
    for (const auto& [id, n] : published) total += n;
    std::printf("published %llu messages\n", static_cast<unsigned long long>(total));
    if (total == 0 && !runner.stopping())
      return fail(path + ": no message could be read or none matched the selection");
    return 0;
  } catch (const std::exception& e) {
    return fail(e.what());
  }
}
