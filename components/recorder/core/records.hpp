#pragma once
// MCAP record types (specification at mcap.dev/spec), their encoding and their parsing.

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace stereoball::recorder {

/// The 8 bytes every MCAP file starts and ends with (major version '0').
inline constexpr std::array<uint8_t, 8> kMagic = {0x89, 'M', 'C', 'A', 'P', 0x30, '\r', '\n'};
/// Bytes of a record's opcode (1) plus content length (8).
inline constexpr uint64_t kRecordPrefixBytes = 9;
/// Bytes of a Footer record including its prefix.
inline constexpr uint64_t kFooterRecordBytes = kRecordPrefixBytes + 20;

/// Record opcodes of the MCAP specification.
enum class Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Human-readable name of an opcode ("Chunk", "unknown 0x42").
std::string opcode_name(uint8_t opcode);

/// Header record: profile and writing library.
struct HeaderRecord {
  std::string profile;
  std::string library;
};

/// Footer record: where the summary sections start and the summary CRC.
struct FooterRecord {
  uint64_t summary_start = 0;
  uint64_t summary_offset_start = 0;
  uint32_t summary_crc = 0;
};

/// Schema record: a type definition (e.g. encoding "omgidl", data = IDL text).
struct SchemaRecord {
  uint16_t id = 0;
  std::string name;
  std::string encoding;
  std::vector<uint8_t> data;
  bool operator==(const SchemaRecord&) const = default;
};

/// Channel record: one topic stream and its message encoding.
struct ChannelRecord {
  uint16_t id = 0;
  uint16_t schema_id = 0;
  std::string topic;
  std::string message_encoding;
  std::map<std::string, std::string> metadata;
  bool operator==(const ChannelRecord&) const = default;
};

/// Message record as a view into a buffer owned by the caller.
struct MessageView {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0;      ///< when the recorder received it
  uint64_t publish_time_ns = 0;  ///< source timestamp
  std::span<const uint8_t> data;
};

/// Chunk record with its records field still compressed (a view).
struct ChunkView {
  uint64_t message_start_time_ns = 0;
  uint64_t message_end_time_ns = 0;
  uint64_t uncompressed_size = 0;
  uint32_t uncompressed_crc = 0;
  std::string compression;
  std::span<const uint8_t> records;
};

/// Message index record: (log time, offset in the uncompressed chunk) per message of a channel.
struct MessageIndexRecord {
  uint16_t channel_id = 0;
  std::vector<std::pair<uint64_t, uint64_t>> entries;
};

/// Chunk index record (summary): where a chunk and its message indexes are.
struct ChunkIndexRecord {
  uint64_t message_start_time_ns = 0;
  uint64_t message_end_time_ns = 0;
  uint64_t chunk_start_offset = 0;
  uint64_t chunk_length = 0;
  std::map<uint16_t, uint64_t> message_index_offsets;
  uint64_t message_index_length = 0;
  std::string compression;
  uint64_t compressed_size = 0;
  uint64_t uncompressed_size = 0;
};

/// Statistics record (summary).
struct StatisticsRecord {
  uint64_t message_count = 0;
  uint16_t schema_count = 0;
  uint32_t channel_count = 0;
  uint32_t attachment_count = 0;
  uint32_t metadata_count = 0;
  uint32_t chunk_count = 0;
  uint64_t message_start_time_ns = 0;
  uint64_t message_end_time_ns = 0;
  std::map<uint16_t, uint64_t> channel_message_counts;
};

/// Summary offset record: location of one group of same-opcode summary records.
struct SummaryOffsetRecord {
  uint8_t group_opcode = 0;
  uint64_t group_start = 0;
  uint64_t group_length = 0;
};

// Encoding: each appends one complete record (opcode, length, content) to out.
void append_header(std::vector<uint8_t>& out, const HeaderRecord& r);
void append_footer(std::vector<uint8_t>& out, const FooterRecord& r);
void append_schema(std::vector<uint8_t>& out, const SchemaRecord& r);
void append_channel(std::vector<uint8_t>& out, const ChannelRecord& r);
void append_message(std::vector<uint8_t>& out, const MessageView& r);
void append_message_index(std::vector<uint8_t>& out, const MessageIndexRecord& r);
void append_chunk_index(std::vector<uint8_t>& out, const ChunkIndexRecord& r);
void append_statistics(std::vector<uint8_t>& out, const StatisticsRecord& r);
void append_summary_offset(std::vector<uint8_t>& out, const SummaryOffsetRecord& r);
void append_data_end(std::vector<uint8_t>& out, uint32_t data_section_crc);

// Parsing: each takes a record's content (after opcode and length); nullopt when malformed.
std::optional<HeaderRecord> parse_header(std::span<const uint8_t> content);
std::optional<FooterRecord> parse_footer(std::span<const uint8_t> content);
std::optional<SchemaRecord> parse_schema(std::span<const uint8_t> content);
std::optional<ChannelRecord> parse_channel(std::span<const uint8_t> content);
std::optional<MessageView> parse_message(std::span<const uint8_t> content);
std::optional<ChunkView> parse_chunk(std::span<const uint8_t> content);
std::optional<MessageIndexRecord> parse_message_index(std::span<const uint8_t> content);
std::optional<ChunkIndexRecord> parse_chunk_index(std::span<const uint8_t> content);
std::optional<StatisticsRecord> parse_statistics(std::span<const uint8_t> content);
std::optional<SummaryOffsetRecord> parse_summary_offset(std::span<const uint8_t> content);

/// One record inside a buffer: opcode and content view.
struct RecordView {
  uint8_t opcode = 0;
  std::span<const uint8_t> content;
};

/// Why a walk over a record sequence ended early.
struct RecordWalkStop {
  uint64_t offset = 0;  ///< offset (within the walked buffer) of the incomplete record
  std::string reason;   ///< e.g. "truncated record"
};

/// Splits buffer into records; calls f(offset, record) for each complete one. f returns false to
/// stop. Returns the reason when the buffer ends inside a record, else nullopt.
template <class F>
std::optional<RecordWalkStop> walk_records(std::span<const uint8_t> buffer, F&& f);

}  // namespace stereoball::recorder

#include "recorder/core/records_walk.inl"
