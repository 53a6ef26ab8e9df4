#include "recorder/core/records.hpp"

#include <cstdio>

#include "recorder/core/byte_io.hpp"

namespace stereoball::recorder {
namespace {

// Writes opcode and a placeholder length; returns the position of the length field.
size_t begin_record(std::vector<uint8_t>& out, Opcode op) {
  ByteWriter w(out);
  w.u8(static_cast<uint8_t>(op));
  const size_t length_pos = out.size();
  w.u64(0);
  return length_pos;
}

// Patches the length field written by begin_record now that the content is complete.
void end_record(std::vector<uint8_t>& out, size_t length_pos) {
  ByteWriter(out).patch_u64(length_pos, out.size() - length_pos - 8);
}

void append_u16_u64_map(ByteWriter& w, const std::map<uint16_t, uint64_t>& m) {
  w.u32(static_cast<uint32_t>(m.size() * 10));
  for (const auto& [k, v] : m) {
    w.u16(k);
    w.u64(v);
  }
}

std::optional<std::map<uint16_t, uint64_t>> parse_u16_u64_map(ByteReader& r) {
  auto bytes = r.bytes32();
  if (!bytes) return std::nullopt;
  ByteReader in(*bytes);
  std::map<uint16_t, uint64_t> m;
  while (in.remaining() > 0) {
    auto k = in.u16();
    auto v = in.u64();
    if (!k || !v) return std::nullopt;
    m[*k] = *v;
  }
  return m;
}

}  // namespace

std::string opcode_name(uint8_t opcode) {
  static const char* const kNames[] = {
      "Header",     "Footer",       "Schema",        "Channel",       "Message",
      "Chunk",      "MessageIndex", "ChunkIndex",    "Attachment",    "AttachmentIndex",
      "Statistics", "Metadata",     "MetadataIndex", "SummaryOffset", "DataEnd"};
  if (opcode >= 0x01 && opcode <= 0x0F) return kNames[opcode - 1];
  char buf[32];
  std::snprintf(buf, sizeof buf, "unknown 0x%02X", opcode);
  return buf;
}

void append_header(std::vector<uint8_t>& out, const HeaderRecord& r) {
  const size_t at = begin_record(out, Opcode::kHeader);
  ByteWriter w(out);
  w.str(r.profile);
  w.str(r.library);
  end_record(out, at);
}

void append_footer(std::vector<uint8_t>& out, const FooterRecord& r) {
  const size_t at = begin_record(out, Opcode::kFooter);
  ByteWriter w(out);
  w.u64(r.summary_start);
  w.u64(r.summary_offset_start);
  w.u32(r.summary_crc);
  end_record(out, at);
}

void append_schema(std::vector<uint8_t>& out, const SchemaRecord& r) {
  const size_t at = begin_record(out, Opcode::kSchema);
  ByteWriter w(out);
  w.u16(r.id);
  w.str(r.name);
  w.str(r.encoding);
  w.u32(static_cast<uint32_t>(r.data.size()));
  w.bytes(r.data);
  end_record(out, at);
}

void append_channel(std::vector<uint8_t>& out, const ChannelRecord& r) {
  const size_t at = begin_record(out, Opcode::kChannel);
  ByteWriter w(out);
  w.u16(r.id);
  w.u16(r.schema_id);
  w.str(r.topic);
  w.str(r.message_encoding);
  const size_t map_pos = out.size();
  w.u32(0);
  for (const auto& [k, v] : r.metadata) {
    w.str(k);
    w.str(v);
  }
  w.patch_u32(map_pos, static_cast<uint32_t>(out.size() - map_pos - 4));
  end_record(out, at);
}

void append_message(std::vector<uint8_t>& out, const MessageView& r) {
  ByteWriter w(out);
  w.u8(static_cast<uint8_t>(Opcode::kMessage));
  w.u64(2 + 4 + 8 + 8 + r.data.size());
  w.u16(r.channel_id);
  w.u32(r.sequence);
  w.u64(r.log_time_ns);
  w.u64(r.publish_time_ns);
  w.bytes(r.data);
}

void append_message_index(std::vector<uint8_t>& out, const MessageIndexRecord& r) {
  const size_t at = begin_record(out, Opcode::kMessageIndex);
  ByteWriter w(out);
  w.u16(r.channel_id);
  w.u32(static_cast<uint32_t>(r.entries.size() * 16));
  for (const auto& [time, offset] : r.entries) {
    w.u64(time);
    w.u64(offset);
  }
  end_record(out, at);
}

void append_chunk_index(std::vector<uint8_t>& out, const ChunkIndexRecord& r) {
  const size_t at = begin_record(out, Opcode::kChunkIndex);
  ByteWriter w(out);
  w.u64(r.message_start_time_ns);
  w.u64(r.message_end_time_ns);
  w.u64(r.chunk_start_offset);
  w.u64(r.chunk_length);
  append_u16_u64_map(w, r.message_index_offsets);
  w.u64(r.message_index_length);
  w.str(r.compression);
  w.u64(r.compressed_size);
  w.u64(r.uncompressed_size);
  end_record(out, at);
}

void append_statistics(std::vector<uint8_t>& out, const StatisticsRecord& r) {
  const size_t at = begin_record(out, Opcode::kStatistics);
  ByteWriter w(out);
  w.u64(r.message_count);
  w.u16(r.schema_count);
  w.u32(r.channel_count);
  w.u32(r.attachment_count);
  w.u32(r.metadata_count);
  w.u32(r.chunk_count);
  w.u64(r.message_start_time_ns);
  w.u64(r.message_end_time_ns);
  append_u16_u64_map(w, r.channel_message_counts);
  end_record(out, at);
}

void append_summary_offset(std::vector<uint8_t>& out, const SummaryOffsetRecord& r) {
  const size_t at = begin_record(out, Opcode::kSummaryOffset);
  ByteWriter w(out);
  w.u8(r.group_opcode);
  w.u64(r.group_start);
  w.u64(r.group_length);
  end_record(out, at);
}

void append_data_end(std::vector<uint8_t>& out, uint32_t data_section_crc) {
  const size_t at = begin_record(out, Opcode::kDataEnd);
  ByteWriter(out).u32(data_section_crc);
  end_record(out, at);
}

std::optional<HeaderRecord> parse_header(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto profile = r.str();
  auto library = r.str();
  if (!profile || !library) return std::nullopt;
  return HeaderRecord{*profile, *library};
}

std::optional<FooterRecord> parse_footer(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto start = r.u64();
  auto offset_start = r.u64();
  auto crc = r.u32();
  if (!start || !offset_start || !crc) return std::nullopt;
  return FooterRecord{*start, *offset_start, *crc};
}

std::optional<SchemaRecord> parse_schema(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto id = r.u16();
  auto name = r.str();
  auto encoding = r.str();
  auto data = r.bytes32();
  if (!id || !name || !encoding || !data) return std::nullopt;
  return SchemaRecord{*id, *name, *encoding, std::vector<uint8_t>(data->begin(), data->end())};
}

std::optional<ChannelRecord> parse_channel(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto id = r.u16();
  auto schema_id = r.u16();
  auto topic = r.str();
  auto encoding = r.str();
  auto map_bytes = r.bytes32();
  if (!id || !schema_id || !topic || !encoding || !map_bytes) return std::nullopt;
  ChannelRecord c{*id, *schema_id, *topic, *encoding, {}};
  ByteReader m(*map_bytes);
  while (m.remaining() > 0) {
    auto k = m.str();
    auto v = m.str();
    if (!k || !v) return std::nullopt;
    c.metadata[*k] = *v;
  }
  return c;
}

std::optional<MessageView> parse_message(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto channel = r.u16();
  auto sequence = r.u32();
  auto log_time = r.u64();
  auto publish_time = r.u64();
  if (!channel || !sequence || !log_time || !publish_time) return std::nullopt;
  return MessageView{*channel, *sequence, *log_time, *publish_time, r.rest()};
}

std::optional<ChunkView> parse_chunk(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto start = r.u64();
  auto end = r.u64();
  auto size = r.u64();
  auto crc = r.u32();
  auto compression = r.str();
  auto records = r.bytes64();
  if (!start || !end || !size || !crc || !compression || !records) return std::nullopt;
  return ChunkView{*start, *end, *size, *crc, *compression, *records};
}

std::optional<MessageIndexRecord> parse_message_index(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto channel = r.u16();
  auto array = r.bytes32();
  if (!channel || !array || array->size() % 16 != 0) return std::nullopt;
  MessageIndexRecord m{*channel, {}};
  for (size_t i = 0; i < array->size(); i += 16) {
    m.entries.emplace_back(load_u64(array->data() + i), load_u64(array->data() + i + 8));
  }
  return m;
}

std::optional<ChunkIndexRecord> parse_chunk_index(std::span<const uint8_t> content) {
  ByteReader r(content);
  ChunkIndexRecord c;
  auto start = r.u64();
  auto end = r.u64();
  auto offset = r.u64();
  auto length = r.u64();
  auto offsets = parse_u16_u64_map(r);
  auto index_length = r.u64();
  auto compression = r.str();
  auto compressed = r.u64();
  auto uncompressed = r.u64();
  if (!start || !end || !offset || !length || !offsets || !index_length || !compression ||
      !compressed || !uncompressed) {
    return std::nullopt;
  }
  return ChunkIndexRecord{*start,        *end,         *offset,     *length,      *offsets,
                          *index_length, *compression, *compressed, *uncompressed};
}

std::optional<StatisticsRecord> parse_statistics(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto messages = r.u64();
  auto schemas = r.u16();
  auto channels = r.u32();
  auto attachments = r.u32();
  auto metadata = r.u32();
  auto chunks = r.u32();
  auto start = r.u64();
  auto end = r.u64();
  auto counts = parse_u16_u64_map(r);
  if (!messages || !schemas || !channels || !attachments || !metadata || !chunks || !start ||
      !end || !counts) {
    return std::nullopt;
  }
  return StatisticsRecord{*messages, *schemas, *channels, *attachments, *metadata,
                          *chunks,   *start,   *end,      *counts};
}

std::optional<SummaryOffsetRecord> parse_summary_offset(std::span<const uint8_t> content) {
  ByteReader r(content);
  auto op = r.u8();
  auto start = r.u64();
  auto length = r.u64();
  if (!op || !start || !length) return std::nullopt;
  return SummaryOffsetRecord{*op, *start, *length};
}

}  // namespace stereoball::recorder
