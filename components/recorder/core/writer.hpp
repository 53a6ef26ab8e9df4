#pragma once
// MCAP writer: schemas, channels and messages in zstd-compressed chunks, each followed by its
// message indexes, then a summary (schemas, channels, statistics, chunk indexes), summary
// offsets and footer. Every chunk is written and flushed to the sink as soon as it is complete,
// so a file cut off after any chunk still holds every message up to that chunk.

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "common/util/result.hpp"
#include "recorder/core/compression.hpp"
#include "recorder/core/crc32.hpp"
#include "recorder/core/io_interfaces.hpp"
#include "recorder/core/records.hpp"

namespace stereoball::recorder {

/// How chunk records are compressed.
enum class Compression { kZstd, kNone };

/// Writer settings.
struct WriterParams {
  uint64_t chunk_size_bytes = 4 << 20;  ///< close a chunk once its uncompressed records reach this
  Compression compression = Compression::kZstd;
  int zstd_level = 1;     ///< zstd level, 1 (fastest) .. 19 (smallest)
  bool chunk_crc = true;  ///< store the CRC-32 of each chunk's uncompressed records
  /// Store the CRC-32 of the whole data section in DataEnd. Off by default: it costs a pass over
  /// every byte written, while chunk CRCs already protect all messages and the summary CRC the
  /// index (the MCAP spec allows 0 = not available).
  bool data_section_crc = false;
  std::string profile;                          ///< MCAP header profile ("" = none)
  std::string library = "stereoball-recorder";  ///< MCAP header library string
  /// Success, or an error naming the bad field and its allowed range.
  Status validate() const;
};

/// Counters of what has been written so far.
struct WriterStats {
  uint64_t messages = 0;
  uint64_t message_bytes = 0;  ///< sum of message payload sizes
  uint64_t chunks = 0;
  uint64_t file_bytes = 0;  ///< bytes handed to the sink
};

/// Writes one MCAP file to a Sink. Not thread-safe; the caller owns threading.
class McapWriter {
 public:
  explicit McapWriter(const WriterParams& params);
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  /// Starts the file on sink (magic and header); sink must outlive the writer. With
  /// index_spill (which must outlive the writer too), the summary's chunk indexes go there in
  /// blocks of kIndexBlockBytes as chunks are finished and are copied into the summary at
  /// close(): the writer's memory then stays the same however many chunks the file gets.
  /// Without it they stay in memory (about 130 bytes a chunk). The file is the same either way.
  Status open(Sink& sink, Spill* index_spill = nullptr);
  /// Registers a schema (e.g. encoding "omgidl", data = IDL text); returns its id (>= 1).
  Result<uint16_t> add_schema(std::string_view name, std::string_view encoding,
                              std::span<const uint8_t> data);
  /// Same, with the schema data given as text.
  Result<uint16_t> add_schema(std::string_view name, std::string_view encoding,
                              std::string_view text);
  /// Registers a channel (topic) on a schema; returns its id.
  Result<uint16_t> add_channel(uint16_t schema_id, std::string_view topic,
                               std::string_view message_encoding,
                               const std::map<std::string, std::string>& metadata = {});
  /// Appends a message (times in ns); the chunk is written out once it reaches the target size.
  Status write(const MessageView& message);
  /// Writes out the current chunk now, even if it is smaller than the target size.
  Status flush_chunk();
  /// Writes the last chunk, the summary and the footer. The writer is finished afterwards.
  Status close();

  /// What has been written so far.
  const WriterStats& stats() const { return stats_; }
  /// Success until an error stops the writer (a sink failure), then that error.
  const Status& status() const { return failure_; }
  /// Bytes the writer holds in its buffers (capacities: open chunk, encoded chunk / index
  /// scratch, chunk indexes not yet spilled). Chunk buffers are sized once, for a chunk of
  /// the target size; they grow only for a message larger than that.
  uint64_t buffer_bytes() const;
  /// Encoded chunk indexes held in memory before they are spilled.
  static constexpr uint64_t kIndexBlockBytes = 64 << 10;

 private:
  Status emit(std::span<const uint8_t> bytes);
  Status finish_chunk();
  Status write_summary_and_footer();
  Status spill_chunk_indexes();
  size_t encoded_chunk_bound(size_t records_bytes) const;
  // Room in the chunk buffer past the target size for the message that crosses it.
  static constexpr size_t kChunkSlackBytes = 64 << 10;
  Status emit_chunk_indexes(Crc32& summary_crc);
  Status check_writable() const;

  WriterParams params_;
  Sink* sink_ = nullptr;
  bool closed_ = false;
  Status failure_;
  std::unique_ptr<ZstdCompressor> compressor_;
  Crc32 data_crc_;
  uint64_t position_ = 0;

  std::vector<SchemaRecord> schemas_;
  std::vector<ChannelRecord> channels_;

  std::vector<uint8_t> chunk_records_;  // uncompressed records of the open chunk
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;  // per channel
  uint64_t chunk_start_ns_ = 0;
  uint64_t chunk_end_ns_ = 0;
  uint64_t chunk_messages_ = 0;
  std::vector<uint8_t> scratch_;  // encoded chunk / index records before they go to the sink

  // The summary's ChunkIndex records, encoded: those not yet spilled, and how many were.
  std::vector<uint8_t> chunk_indexes_;
  Spill* index_spill_ = nullptr;
  uint64_t index_spill_base_ = 0;  // the spill's size when the writer started
  uint64_t spilled_index_bytes_ = 0;
  uint32_t chunk_count_ = 0;
  StatisticsRecord statistics_;
  WriterStats stats_;
};

}  // namespace stereoball::recorder
