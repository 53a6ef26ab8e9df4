#pragma once
// What `stereoball info` reports about a recording: time span, per-topic counts, rates and sizes,
// and whether the file is complete.

#include <cstdint>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "recorder/core/reader.hpp"

namespace stereoball::recorder {

/// Figures for one channel (topic).
struct TopicInfo {
  std::string topic;
  std::string type;  ///< schema name, e.g. "stereoball::msg::StereoFrame"
  std::string message_encoding;
  uint64_t messages = 0;
  uint64_t bytes = 0;  ///< sum of message payload sizes
  uint64_t first_log_ns = 0;
  uint64_t last_log_ns = 0;
  double rate_hz = 0.0;  ///< (messages - 1) / (last - first); 0 with fewer than 2 messages
};

/// Figures for a whole file.
struct FileInfo {
  uint64_t file_bytes = 0;
  std::string library;
  bool complete = false;         ///< footer present (recording was closed properly)
  bool indexed = false;          ///< read through the summary
  uint64_t messages = 0;         ///< messages read
  uint64_t listed_messages = 0;  ///< messages the file's summary lists (0 without a summary)
  uint64_t chunks = 0;
  uint64_t start_ns = 0;  ///< earliest log time
  uint64_t end_ns = 0;    ///< latest log time
  std::vector<TopicInfo> topics;
  std::vector<std::string> notes;

  /// True when the file holds or lists something but not one message could be read: the
  /// tools then fail instead of reporting an empty recording.
  bool nothing_readable() const {
    return messages == 0 && (listed_messages > 0 || chunks > 0 || !notes.empty());
  }
};

/// Opens source and reads every message to build the figures; error for non-MCAP input.
Result<FileInfo> collect_file_info(Source& source);

/// Human-readable report (several lines, ends with a newline).
std::string format_file_info(const FileInfo& info, const std::string& path);

/// UTC time of ns since the epoch as "2026-11-21 22:41:13.123456789 UTC".
std::string format_utc(uint64_t ns);

}  // namespace stereoball::recorder
