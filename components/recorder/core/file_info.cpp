#include "recorder/core/file_info.hpp"

#include <cinttypes>
#include <cstdio>
#include <ctime>
#include <map>

namespace stereoball::recorder {

Result<FileInfo> collect_file_info(Source& source) {
  McapReader reader(source);
  if (auto err = reader.open(); !err) return Error{err.error()};
  std::map<uint16_t, TopicInfo> per_channel;
  FileInfo info;
  if (auto err = reader.for_each_message([&](const MessageView& m) {
        TopicInfo& t = per_channel[m.channel_id];
        if (t.messages == 0) t.first_log_ns = t.last_log_ns = m.log_time_ns;
        t.first_log_ns = std::min(t.first_log_ns, m.log_time_ns);
        t.last_log_ns = std::max(t.last_log_ns, m.log_time_ns);
        ++t.messages;
        t.bytes += m.data.size();
        if (info.messages == 0) info.start_ns = info.end_ns = m.log_time_ns;
        info.start_ns = std::min(info.start_ns, m.log_time_ns);
        info.end_ns = std::max(info.end_ns, m.log_time_ns);
        ++info.messages;
        return true;
      });
      !err) {
    return Error{err.error()};
  }
  const auto& summary = reader.summary();
  for (const auto& [id, channel] : summary.channels) {
    TopicInfo t = per_channel[id];
    t.topic = channel.topic;
    t.message_encoding = channel.message_encoding;
    const auto schema = summary.schemas.find(channel.schema_id);
    t.type = schema != summary.schemas.end() ? schema->second.name : "(no schema)";
    if (t.messages >= 2 && t.last_log_ns > t.first_log_ns) {
      t.rate_hz = static_cast<double>(t.messages - 1) * 1e9 /
                  static_cast<double>(t.last_log_ns - t.first_log_ns);
    }
    info.topics.push_back(std::move(t));
  }
  info.file_bytes = source.size();
  info.library = summary.header.library;
  info.complete = summary.complete;
  info.indexed = summary.indexed;
  info.chunks = summary.statistics.chunk_count;
  info.listed_messages = summary.listed_messages;
  info.notes = reader.notes();
  return info;
}

std::string format_utc(uint64_t ns) {
  const std::time_t secs = static_cast<std::time_t>(ns / 1'000'000'000ull);
  std::tm tm{};
  gmtime_r(&secs, &tm);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S", &tm);
  char out[64];
  std::snprintf(out, sizeof out, "%s.%09" PRIu64 " UTC", date,
                static_cast<uint64_t>(ns % 1'000'000'000u));
  return out;
}

namespace {

std::string human_bytes(uint64_t b) {
  char buf[32];
  if (b >= 1'000'000'000)
    std::snprintf(buf, sizeof buf, "%.2f GB", b / 1e9);
  else if (b >= 1'000'000)
    std::snprintf(buf, sizeof buf, "%.2f MB", b / 1e6);
  else if (b >= 1'000)
    std::snprintf(buf, sizeof buf, "%.2f kB", b / 1e3);
  else
    std::snprintf(buf, sizeof buf, "%" PRIu64 " B", b);
  return buf;
}

}  // namespace

std::string format_file_info(const FileInfo& info, const std::string& path) {
  std::string out;
  char line[512];
  auto add = [&](const char* fmt, auto... args) {
    std::snprintf(line, sizeof line, fmt, args...);
    out += line;
  };
  add("file:      %s (%s)\n", path.c_str(), human_bytes(info.file_bytes).c_str());
  add("complete:  %s\n", !info.complete ? "NO (no footer: recording was interrupted)"
                         : info.messages < info.listed_messages
                             ? "NO (closed properly, but not every message listed could be read)"
                             : "yes (closed properly: footer and summary present)");
  add("read:      %s\n", info.indexed ? "indexed (summary)" : "linear scan");
  add("library:   %s\n", info.library.c_str());
  if (info.messages > 0) {
    add("start:     %s\n", format_utc(info.start_ns).c_str());
    add("end:       %s\n", format_utc(info.end_ns).c_str());
    add("duration:  %.3f s\n", static_cast<double>(info.end_ns - info.start_ns) / 1e9);
  } else {
    add("duration:  (no messages)\n");
  }
  add("messages:  %" PRIu64 " in %" PRIu64 " chunks\n", info.messages, info.chunks);
  if (info.messages < info.listed_messages)
    add("unread:    %" PRIu64 " of the %" PRIu64 " messages the summary lists\n",
        info.listed_messages - info.messages, info.listed_messages);
  add("topics:    %zu\n", info.topics.size());
  size_t topic_w = 5, type_w = 4;
  for (const auto& t : info.topics) {
    topic_w = std::max(topic_w, t.topic.size());
    type_w = std::max(type_w, t.type.size());
  }
  add("  %-*s  %-*s  %10s  %10s  %10s\n", static_cast<int>(topic_w), "topic",
      static_cast<int>(type_w), "type", "messages", "rate Hz", "size");
  for (const auto& t : info.topics) {
    add("  %-*s  %-*s  %10" PRIu64 "  %10.2f  %10s\n", static_cast<int>(topic_w), t.topic.c_str(),
        static_cast<int>(type_w), t.type.c_str(), t.messages, t.rate_hz,
        human_bytes(t.bytes).c_str());
  }
  for (const auto& n : info.notes) add("note:      %s\n", n.c_str());
  return out;
}

}  // namespace stereoball::recorder
