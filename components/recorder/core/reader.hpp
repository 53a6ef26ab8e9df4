#pragma once
// MCAP reader: indexed reading through the summary when the file has one, otherwise a linear
// scan that stops cleanly at the first truncated or corrupt record and keeps everything complete
// before it. Problems that do not prevent reading (CRC mismatch, truncation) become notes.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "recorder/core/io_interfaces.hpp"
#include "recorder/core/records.hpp"

namespace stereoball::recorder {

/// What opening a file revealed: definitions, statistics and how the file was read.
struct FileSummary {
  HeaderRecord header;
  std::map<uint16_t, SchemaRecord> schemas;
  std::map<uint16_t, ChannelRecord> channels;
  StatisticsRecord statistics;   ///< from the file's summary, or counted by the linear scan
  bool complete = false;         ///< footer and trailing magic present
  bool indexed = false;          ///< messages are read through the summary's chunk indexes
  uint64_t listed_messages = 0;  ///< message count of the file's Statistics record (0 = none)
};

/// Memory the reader may spend on one record: every size a file states is checked against the
/// file's own size and these limits before anything is allocated for it.
struct ReaderLimits {
  /// Largest chunk (uncompressed) or other record read into memory; larger ones are skipped
  /// with a note. The recorder writes 4 MiB chunks (one bigger only for a bigger message).
  uint64_t max_record_bytes = uint64_t{64} << 20;
};

/// Reads one MCAP file from a Source. Not thread-safe.
class McapReader {
 public:
  /// Reads from source, which must outlive the reader.
  explicit McapReader(Source& source, ReaderLimits limits = {});

  /// Checks magic and header, then loads the summary or scans linearly; fails only when the
  /// input is not an MCAP file at all (bad magic, no header).
  Status open();
  /// Definitions and statistics (valid after a successful open()).
  const FileSummary& summary() const { return summary_; }
  /// Calls f(message) for every complete message in file order; f returns false to stop early.
  /// The message data view is valid only during the call.
  Status for_each_message(const std::function<bool(const MessageView&)>& f);
  /// Checks every chunk's message indexes against the chunk's messages (indexed files only);
  /// returns the first inconsistency found.
  Status check_message_indexes();
  /// Chunk indexes from the summary, ordered by file offset (empty when scanned linearly).
  const std::vector<ChunkIndexRecord>& chunk_indexes() const { return chunk_indexes_; }
  /// Problems met so far that did not stop reading, e.g. "no summary, scanned linearly".
  const std::vector<std::string>& notes() const { return notes_; }

 private:
  using MessageFn = std::function<bool(const MessageView&)>;
  enum class Visit { kContinue, kStop, kCorrupt };
  Status read_header();
  bool try_read_summary();
  // True when every chunk index points at a Chunk record of its stated length in the file.
  bool chunk_indexes_valid();
  Status scan_linear(const MessageFn* f);
  // Decompresses and CRC-checks a chunk at file offset; false when it was skipped (noted).
  bool load_chunk(uint64_t offset, const ChunkView& chunk);
  // Walks the loaded chunk's records.
  Visit visit_chunk(uint64_t offset, const MessageFn* f);
  Visit handle_record(uint64_t offset, const RecordView& r, const MessageFn* f, bool in_chunk);
  void note(std::string text);

  Source& source_;
  ReaderLimits limits_;
  FileSummary summary_;
  std::vector<ChunkIndexRecord> chunk_indexes_;
  std::vector<uint8_t> record_;        // content of the record being read from the source
  std::vector<uint8_t> decompressed_;  // records of the current chunk
  std::vector<std::string> notes_;
  StatisticsRecord counted_;  // statistics counted during a linear scan
  bool opened_ = false;
};

}  // namespace stereoball::recorder
