#pragma once
// A recording in progress: a bounded queue filled by the DDS side and a writer thread that
// turns it into MCAP files (optionally split by size or duration). When the disk cannot keep
// up, the queue fills and further messages are dropped and counted, never silently, and
// memory stays bounded by queue_limit_bytes.

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "common/util/result.hpp"
#include "recorder/core/writer.hpp"
#include "recorder/io/file_io.hpp"

namespace stereoball::recorder {

/// Settings of a recording.
struct RecordingParams {
  std::string path = "recording.mcap";  ///< output; with splitting: <stem>_000.mcap, _001, ...
  uint64_t split_size_bytes = 0;        ///< start a new file past this size (0 = never)
  int64_t split_duration_ns = 0;        ///< start a new file past this log-time span (0 = never)
  uint64_t queue_limit_bytes = 256ull << 20;      ///< queued payload bytes before dropping
  int64_t chunk_flush_period_ns = 1'000'000'000;  ///< write out a non-full chunk this old
  WriterParams writer;
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// A topic to record: name, type (schema name) and the IDL text stored as its schema.
struct RecordedTopic {
  std::string topic;
  std::string type_name;
  std::string schema_text;
};

/// Per-topic counters since the start.
struct TopicCounters {
  uint64_t messages = 0;  ///< written to a file
  uint64_t bytes = 0;     ///< payload bytes written
  uint64_t dropped = 0;   ///< refused because the queue was full or the writer had failed
};

/// Recording session (thread-safe push, one internal writer thread).
class Recording {
 public:
  /// Opens the first file and starts the writer thread; error names the file or bad field.
  static Result<std::unique_ptr<Recording>> start(const RecordingParams& params,
                                                  std::vector<RecordedTopic> topics);
  ~Recording();
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;

  /// Queues one serialized sample of topics[topic_index] (times in ns since the epoch);
  /// false when it was dropped.
  bool push(size_t topic_index, std::vector<uint8_t> cdr, uint64_t log_time_ns,
            uint64_t publish_time_ns);
  /// Counters per topic, in the order given to start().
  std::vector<TopicCounters> counters() const;
  /// Bytes currently queued.
  uint64_t queued_bytes() const;
  /// Success, or the first write error (e.g. disk full); the files stay readable up to the
  /// last completed chunk.
  Status status() const;
  /// Files written so far (the last one is open until stop()).
  std::vector<std::string> files() const;
  /// Writes everything queued, closes the file (summary and footer), joins the thread.
  Status stop();

 private:
  struct Item {
    size_t topic;
    uint32_t sequence;
    uint64_t log_ns;
    uint64_t publish_ns;
    std::vector<uint8_t> cdr;
  };
  Recording(const RecordingParams& params, std::vector<RecordedTopic> topics);
  Status open_file();
  Status close_file();
  void run();
  Status write_item(const Item& item);
  void fail(const std::string& what);
  std::string file_path(size_t index) const;

  RecordingParams params_;
  std::vector<RecordedTopic> topics_;

  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Item> queue_;
  uint64_t queued_bytes_ = 0;
  bool stopping_ = false;
  std::vector<TopicCounters> counters_;
  std::vector<uint32_t> sequences_;
  Status failure_;
  std::vector<std::string> files_;

  // Owned by the writer thread once started.
  std::unique_ptr<FileSink> sink_;
  std::unique_ptr<FileSpill> index_spill_;  // the writer's chunk indexes, out of memory
  std::unique_ptr<McapWriter> writer_;
  std::vector<uint16_t> channel_ids_;
  uint64_t file_first_log_ns_ = 0;
  bool file_has_messages_ = false;
  std::thread thread_;
};

}  // namespace stereoball::recorder
