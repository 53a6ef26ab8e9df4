#include "recorder/core/reader.hpp"

#include <algorithm>
#include <array>
#include <cstdio>

#include "recorder/core/byte_io.hpp"
#include "recorder/core/compression.hpp"
#include "recorder/core/crc32.hpp"

namespace stereoball::recorder {
namespace {

constexpr const char* kLinearNote = "no summary, scanned linearly";

std::string hex32(uint32_t v) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "0x%08X", v);
  return buf;
}

std::string at(uint64_t offset) {
  return "offset " + std::to_string(offset);
}

// Reads one record (prefix and content) at offset; content is resized to the record length.
Status read_record(Source& source, uint64_t offset, uint64_t max_bytes, uint8_t& opcode,
                   std::vector<uint8_t>& content) {
  const uint64_t size = source.size();
  if (offset > size || size - offset < kRecordPrefixBytes) {
    return Error{"record at " + at(offset) + " is past the end of the file"};
  }
  std::array<uint8_t, kRecordPrefixBytes> prefix{};
  if (auto err = source.read(offset, prefix); !err) return err;
  const uint64_t length = load_u64(prefix.data() + 1);
  if (length > size - offset - kRecordPrefixBytes) {
    return Error{"truncated " + opcode_name(prefix[0]) + " record at " + at(offset) + ": needs " +
                 std::to_string(length) + " bytes, " +
                 std::to_string(size - offset - kRecordPrefixBytes) + " left"};
  }
  if (length > max_bytes) {
    return Error{opcode_name(prefix[0]) + " record at " + at(offset) + " has " +
                 std::to_string(length) + " bytes, more than the reader's limit of " +
                 std::to_string(max_bytes)};
  }
  opcode = prefix[0];
  content.resize(length);
  return source.read(offset + kRecordPrefixBytes, content);
}

void count_message(StatisticsRecord& s, const MessageView& m) {
  if (s.message_count == 0) s.message_start_time_ns = s.message_end_time_ns = m.log_time_ns;
  s.message_start_time_ns = std::min(s.message_start_time_ns, m.log_time_ns);
  s.message_end_time_ns = std::max(s.message_end_time_ns, m.log_time_ns);
  ++s.message_count;
  ++s.channel_message_counts[m.channel_id];
}

}  // namespace

McapReader::McapReader(Source& source, ReaderLimits limits) : source_(source), limits_(limits) {}

void McapReader::note(std::string text) {
  if (std::find(notes_.begin(), notes_.end(), text) == notes_.end()) {
    notes_.push_back(std::move(text));
  }
}

Status McapReader::read_header() {
  const uint64_t size = source_.size();
  if (size == 0) return Error{"not an MCAP file: the file is empty (0 bytes)"};
  std::array<uint8_t, 8> magic{};
  if (size < magic.size() || !source_.read(0, magic).ok() || magic != kMagic) {
    return Error{"not an MCAP file: bad magic"};
  }
  uint8_t first = 0;
  if (size > magic.size() && source_.read(magic.size(), std::span(&first, 1)).ok() &&
      first != static_cast<uint8_t>(Opcode::kHeader)) {
    return Error{"not an MCAP file: first record is " + opcode_name(first) + ", expected Header"};
  }
  uint8_t opcode = 0;
  if (auto err = read_record(source_, magic.size(), limits_.max_record_bytes, opcode, record_);
      !err) {
    return Error{"MCAP file truncated inside its Header record: " + err.error()};
  }
  auto header = parse_header(record_);
  if (!header) return Error{"corrupt MCAP header record at offset 8"};
  summary_.header = *header;
  return {};
}

Status McapReader::open() {
  if (auto err = read_header(); !err) return err;
  summary_.indexed = try_read_summary() && chunk_indexes_valid();
  if (!summary_.indexed) {
    summary_.schemas.clear();
    summary_.channels.clear();
    chunk_indexes_.clear();
    if (auto err = scan_linear(nullptr); !err) return err;
    summary_.statistics = counted_;
  }
  opened_ = true;
  return {};
}

bool McapReader::try_read_summary() {
  const uint64_t size = source_.size();
  const uint64_t tail_bytes = kFooterRecordBytes + kMagic.size();
  std::array<uint8_t, kFooterRecordBytes + 8> tail{};
  const bool has_tail =
      size >= kMagic.size() + tail_bytes && source_.read(size - tail_bytes, tail).ok();
  const bool footer_ok = has_tail && std::equal(kMagic.begin(), kMagic.end(), tail.end() - 8) &&
                         tail[0] == static_cast<uint8_t>(Opcode::kFooter) &&
                         load_u64(tail.data() + 1) == 20;
  if (!footer_ok) {
    note(std::string("no footer: the file is incomplete (its writer never closed it); ") +
         kLinearNote);
    return false;
  }
  summary_.complete = true;
  const auto footer = *parse_footer(std::span(tail).subspan(kRecordPrefixBytes, 20));
  const uint64_t footer_pos = size - tail_bytes;
  if (footer.summary_start == 0) {
    note(std::string("file has a footer but ") + kLinearNote);
    return false;
  }
  if (footer.summary_start < 8 || footer.summary_start > footer_pos ||
      (footer.summary_offset_start != 0 && (footer.summary_offset_start < footer.summary_start ||
                                            footer.summary_offset_start > footer_pos))) {
    note("footer points outside the file (summary_start " + std::to_string(footer.summary_start) +
         "); " + kLinearNote);
    return false;
  }
  // Summary, summary offsets and the footer up to (not including) its CRC field.
  if (footer_pos - footer.summary_start > limits_.max_record_bytes) {
    note(std::string("summary is larger than the reader's limit; ") + kLinearNote);
    return false;
  }
  std::vector<uint8_t> region(footer_pos + kRecordPrefixBytes + 16 - footer.summary_start);
  if (!source_.read(footer.summary_start, region).ok()) {
    note(std::string("summary could not be read; ") + kLinearNote);
    return false;
  }
  if (footer.summary_crc != 0 && crc32(region) != footer.summary_crc) {
    note("summary CRC mismatch (stored " + hex32(footer.summary_crc) + ", computed " +
         hex32(crc32(region)) + "); summary ignored, " + kLinearNote);
    return false;
  }
  const uint64_t records_end =
      footer.summary_offset_start != 0 ? footer.summary_offset_start : footer_pos;
  bool ok = true;
  bool has_statistics = false;
  auto stop = walk_records(std::span(region).first(records_end - footer.summary_start),
                           [&](uint64_t, const RecordView& r) {
                             switch (static_cast<Opcode>(r.opcode)) {
                               case Opcode::kSchema:
                                 if (auto s = parse_schema(r.content))
                                   summary_.schemas[s->id] = *s;
                                 else
                                   ok = false;
                                 break;
                               case Opcode::kChannel:
                                 if (auto c = parse_channel(r.content))
                                   summary_.channels[c->id] = *c;
                                 else
                                   ok = false;
                                 break;
                               case Opcode::kStatistics:
                                 if (auto s = parse_statistics(r.content)) {
                                   summary_.statistics = *s;
                                   summary_.listed_messages = s->message_count;
                                 } else
                                   ok = false;
                                 has_statistics = true;
                                 break;
                               case Opcode::kChunkIndex:
                                 if (auto c = parse_chunk_index(r.content))
                                   chunk_indexes_.push_back(*c);
                                 else
                                   ok = false;
                                 break;
                               default:
                                 break;
                             }
                             return ok;
                           });
  if (stop || !ok) {
    note(std::string("corrupt summary section; ") + kLinearNote);
    return false;
  }
  if (!has_statistics) {
    note(std::string("summary has no statistics record; ") + kLinearNote);
    return false;
  }
  std::sort(chunk_indexes_.begin(), chunk_indexes_.end(), [](const auto& a, const auto& b) {
    return a.chunk_start_offset < b.chunk_start_offset;
  });
  return true;
}

bool McapReader::chunk_indexes_valid() {
  const uint64_t size = source_.size();
  std::array<uint8_t, kRecordPrefixBytes> prefix{};
  for (const auto& index : chunk_indexes_) {
    const uint64_t at_offset = index.chunk_start_offset;
    const bool fits = at_offset >= kMagic.size() && at_offset <= size &&
                      size - at_offset >= kRecordPrefixBytes &&
                      index.chunk_length <= size - at_offset;
    const bool is_chunk = fits && source_.read(at_offset, prefix).ok() &&
                          prefix[0] == static_cast<uint8_t>(Opcode::kChunk) &&
                          kRecordPrefixBytes + load_u64(prefix.data() + 1) == index.chunk_length;
    if (!is_chunk) {
      note("chunk index points to " + at(at_offset) + ", which holds no chunk of " +
           std::to_string(index.chunk_length) + " bytes; indexes ignored, " + kLinearNote);
      return false;
    }
  }
  return true;
}

Status McapReader::scan_linear(const MessageFn* f) {
  const uint64_t size = source_.size();
  counted_ = {};
  Crc32 data_crc;
  data_crc.update(kMagic);
  uint64_t pos = kMagic.size();
  bool crc_skipped = false;
  std::array<uint8_t, kRecordPrefixBytes> prefix{};
  while (true) {
    if (pos == size) {
      note("file ends at " + at(pos) + " without a DataEnd record; read everything before it");
      break;
    }
    if (size - pos < kRecordPrefixBytes) {
      note("truncated record at " + at(pos) + " (" + std::to_string(size - pos) +
           " bytes left); stopped there, everything before it was read");
      break;
    }
    if (auto err = source_.read(pos, prefix); !err) return err;
    const uint8_t opcode = prefix[0];
    const uint64_t length = load_u64(prefix.data() + 1);
    if (length > size - pos - kRecordPrefixBytes) {
      note("truncated " + opcode_name(opcode) + " record at " + at(pos) + " (needs " +
           std::to_string(length) + " bytes, " + std::to_string(size - pos - kRecordPrefixBytes) +
           " left); stopped there, everything before it was read");
      break;
    }
    if (opcode == 0) {
      note("corrupt record at " + at(pos) + " (opcode 0x00); stopped there");
      break;
    }
    if (length > limits_.max_record_bytes) {
      note(opcode_name(opcode) + " record at " + at(pos) + " has " + std::to_string(length) +
           " bytes, more than the reader's limit of " + std::to_string(limits_.max_record_bytes) +
           "; skipped");
      crc_skipped = true;  // the data CRC cannot be checked without reading every byte
      pos += kRecordPrefixBytes + length;
      continue;
    }
    record_.resize(length);
    if (auto err = source_.read(pos + kRecordPrefixBytes, record_); !err) return err;
    if (opcode == static_cast<uint8_t>(Opcode::kDataEnd)) {
      ByteReader r(record_);
      const auto stored = r.u32();
      if (!crc_skipped && stored && *stored != 0 && *stored != data_crc.value()) {
        note("data section CRC mismatch (stored " + hex32(*stored) + ", computed " +
             hex32(data_crc.value()) + ")");
      }
      break;
    }
    if (opcode == static_cast<uint8_t>(Opcode::kFooter)) break;
    data_crc.update(prefix);
    data_crc.update(record_);
    const Visit v = handle_record(pos, {opcode, record_}, f, false);
    if (v == Visit::kStop) return {};
    if (v == Visit::kCorrupt) break;
    pos += kRecordPrefixBytes + length;
  }
  counted_.schema_count = static_cast<uint16_t>(summary_.schemas.size());
  counted_.channel_count = static_cast<uint32_t>(summary_.channels.size());
  return {};
}

McapReader::Visit McapReader::handle_record(uint64_t offset, const RecordView& r,
                                            const MessageFn* f, bool in_chunk) {
  const std::string where = (in_chunk ? "chunk record at " : "record at ") + at(offset);
  switch (static_cast<Opcode>(r.opcode)) {
    case Opcode::kSchema: {
      auto s = parse_schema(r.content);
      if (!s) break;
      summary_.schemas[s->id] = std::move(*s);
      return Visit::kContinue;
    }
    case Opcode::kChannel: {
      auto c = parse_channel(r.content);
      if (!c) break;
      summary_.channels[c->id] = std::move(*c);
      return Visit::kContinue;
    }
    case Opcode::kMessage: {
      auto m = parse_message(r.content);
      if (!m) break;
      count_message(counted_, *m);
      return (f != nullptr && !(*f)(*m)) ? Visit::kStop : Visit::kContinue;
    }
    case Opcode::kChunk: {
      if (in_chunk) return Visit::kContinue;
      auto chunk = parse_chunk(r.content);
      if (!chunk) break;
      ++counted_.chunk_count;
      if (!load_chunk(offset, *chunk)) return Visit::kContinue;
      return visit_chunk(offset, f);
    }
    default:
      return Visit::kContinue;
  }
  note("corrupt " + opcode_name(r.opcode) + " " + where + "; stopped there");
  return Visit::kCorrupt;
}

bool McapReader::load_chunk(uint64_t offset, const ChunkView& chunk) {
  const std::string where = "chunk at " + at(offset) + ": ";
  if (chunk.compression == "zstd") {
    if (auto err = zstd_decompress(chunk.records, chunk.uncompressed_size, decompressed_,
                                   limits_.max_record_bytes);
        !err) {
      note(where + err.error() + "; its messages skipped");
      return false;
    }
  } else if (chunk.compression.empty()) {
    if (chunk.records.size() != chunk.uncompressed_size) {
      note(where + "records size does not match uncompressed_size; its messages skipped");
      return false;
    }
    decompressed_.assign(chunk.records.begin(), chunk.records.end());
  } else {
    note(where + "unsupported compression '" + chunk.compression + "'; its messages skipped");
    return false;
  }
  if (chunk.uncompressed_crc != 0) {
    const uint32_t crc = crc32(decompressed_);
    if (crc != chunk.uncompressed_crc) {
      note(where + "CRC mismatch (stored " + hex32(chunk.uncompressed_crc) + ", computed " +
           hex32(crc) + "); its messages skipped");
      return false;
    }
  }
  return true;
}

McapReader::Visit McapReader::visit_chunk(uint64_t offset, const MessageFn* f) {
  Visit result = Visit::kContinue;
  auto stop = walk_records(std::span<const uint8_t>(decompressed_),
                           [&](uint64_t inner, const RecordView& r) {
                             result = handle_record(inner, r, f, true);
                             return result == Visit::kContinue;
                           });
  if (stop) {
    note("chunk at " + at(offset) + ": " + stop->reason + " at inner offset " +
         std::to_string(stop->offset) + "; rest of the chunk skipped");
  }
  if (result == Visit::kCorrupt) {
    note("chunk at " + at(offset) + " holds a corrupt record; rest of the chunk skipped");
    return Visit::kContinue;
  }
  return result;
}

Status McapReader::for_each_message(const MessageFn& f) {
  if (!opened_) return Error{"MCAP reader is not open"};
  if (!summary_.indexed) return scan_linear(&f);
  uint8_t opcode = 0;
  for (const auto& index : chunk_indexes_) {
    if (auto err = read_record(source_, index.chunk_start_offset, limits_.max_record_bytes, opcode,
                               record_);
        !err) {
      note("chunk index points to an unreadable chunk: " + err.error() + "; skipped");
      continue;
    }
    auto chunk = parse_chunk(record_);
    if (opcode != static_cast<uint8_t>(Opcode::kChunk) || !chunk) {
      note("chunk index points to a corrupt chunk at " + at(index.chunk_start_offset) +
           "; skipped");
      continue;
    }
    if (!load_chunk(index.chunk_start_offset, *chunk)) continue;
    if (visit_chunk(index.chunk_start_offset, &f) == Visit::kStop) return {};
  }
  return {};
}

Status McapReader::check_message_indexes() {
  if (!opened_) return Error{"MCAP reader is not open"};
  if (!summary_.indexed) return Error{"file has no summary: message indexes not checkable"};
  using Entries = std::vector<std::pair<uint64_t, uint64_t>>;
  uint8_t opcode = 0;
  for (const auto& index : chunk_indexes_) {
    const std::string where = "chunk at " + at(index.chunk_start_offset) + ": ";
    if (auto err = read_record(source_, index.chunk_start_offset, limits_.max_record_bytes, opcode,
                               record_);
        !err)
      return err;
    auto chunk = parse_chunk(record_);
    if (!chunk || !load_chunk(index.chunk_start_offset, *chunk)) return Error{where + "unreadable"};
    std::map<uint16_t, Entries> actual;
    walk_records(std::span<const uint8_t>(decompressed_), [&](uint64_t inner, const RecordView& r) {
      if (r.opcode == static_cast<uint8_t>(Opcode::kMessage)) {
        if (auto m = parse_message(r.content))
          actual[m->channel_id].emplace_back(m->log_time_ns, inner);
      }
      return true;
    });
    if (actual.size() != index.message_index_offsets.size()) {
      return Error{where + "has messages on " + std::to_string(actual.size()) + " channels but " +
                   std::to_string(index.message_index_offsets.size()) + " message indexes"};
    }
    for (const auto& [channel, offset] : index.message_index_offsets) {
      if (auto err = read_record(source_, offset, limits_.max_record_bytes, opcode, record_); !err)
        return Error{where + err.error()};
      auto mi = parse_message_index(record_);
      if (opcode != static_cast<uint8_t>(Opcode::kMessageIndex) || !mi ||
          mi->channel_id != channel) {
        return Error{where + "message index of channel " + std::to_string(channel) + " is corrupt"};
      }
      Entries expected = actual[channel];
      std::sort(expected.begin(), expected.end());
      std::sort(mi->entries.begin(), mi->entries.end());
      if (mi->entries != expected) {
        return Error{where + "message index of channel " + std::to_string(channel) +
                     " does not match the chunk's messages"};
      }
    }
  }
  return {};
}

}  // namespace stereoball::recorder
