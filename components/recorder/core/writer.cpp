#include "recorder/core/writer.hpp"

#include <algorithm>

#include "recorder/core/byte_io.hpp"

namespace stereoball::recorder {

Status WriterParams::validate() const {
  if (chunk_size_bytes < 1024 || chunk_size_bytes > (uint64_t{1} << 30)) {
    return Error{"chunk_size_bytes must be in [1024, 1073741824], got " +
                 std::to_string(chunk_size_bytes)};
  }
  if (zstd_level < 1 || zstd_level > 19) {
    return Error{"zstd_level must be in [1, 19], got " + std::to_string(zstd_level)};
  }
  return {};
}

McapWriter::McapWriter(const WriterParams& params) : params_(params) {
  if (params_.compression == Compression::kZstd) {
    compressor_ = std::make_unique<ZstdCompressor>(params_.zstd_level);
  }
}

McapWriter::~McapWriter() = default;

Status McapWriter::check_writable() const {
  if (!failure_.ok()) return failure_;
  if (sink_ == nullptr) return Error{"MCAP writer is not open"};
  if (closed_) return Error{"MCAP writer is already closed"};
  return {};
}

Status McapWriter::emit(std::span<const uint8_t> bytes) {
  if (auto err = sink_->write(bytes); !err) {
    failure_ =
        Error{"write failed at file offset " + std::to_string(position_) + ": " + err.error()};
    return failure_;
  }
  if (params_.data_section_crc) data_crc_.update(bytes);
  position_ += bytes.size();
  stats_.file_bytes = position_;
  return {};
}

Status McapWriter::open(Sink& sink, Spill* index_spill) {
  if (auto bad = params_.validate(); !bad) return bad;
  if (sink_ != nullptr) return Error{"MCAP writer is already open"};
  sink_ = &sink;
  index_spill_ = index_spill;
  index_spill_base_ = index_spill ? index_spill->size() : 0;
  // Room for a block of indexes and the record that crosses it (the block is spilled then).
  if (index_spill_ != nullptr) chunk_indexes_.reserve(2 * kIndexBlockBytes);
  // Sized once for a full chunk (pages become resident only as they are written): buffers
  // reallocated to sizes that depend on the data (the first message of a chunk, a burst)
  // left holes in the allocator's arenas that a long recording never got back.
  chunk_records_.reserve(params_.chunk_size_bytes + kChunkSlackBytes);
  scratch_.reserve(encoded_chunk_bound(params_.chunk_size_bytes + kChunkSlackBytes));
  scratch_.assign(kMagic.begin(), kMagic.end());
  append_header(scratch_, HeaderRecord{params_.profile, params_.library});
  return emit(scratch_);
}

Result<uint16_t> McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                        std::span<const uint8_t> data) {
  if (auto err = check_writable(); !err) return Error{err.error()};
  if (schemas_.size() >= 0xFFFE) return Error{"too many schemas (max 65534)"};
  SchemaRecord schema{static_cast<uint16_t>(schemas_.size() + 1), std::string(name),
                      std::string(encoding), std::vector<uint8_t>(data.begin(), data.end())};
  // Outside chunks, so the definition survives even if the next chunk is cut off.
  scratch_.clear();
  append_schema(scratch_, schema);
  if (auto err = emit(scratch_); !err) return Error{err.error()};
  schemas_.push_back(std::move(schema));
  return schemas_.back().id;
}

Result<uint16_t> McapWriter::add_schema(std::string_view name, std::string_view encoding,
                                        std::string_view text) {
  return add_schema(
      name, encoding,
      std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

Result<uint16_t> McapWriter::add_channel(uint16_t schema_id, std::string_view topic,
                                         std::string_view message_encoding,
                                         const std::map<std::string, std::string>& metadata) {
  if (auto err = check_writable(); !err) return Error{err.error()};
  if (schema_id > schemas_.size()) {
    return Error{"channel '" + std::string(topic) + "' refers to unknown schema " +
                 std::to_string(schema_id)};
  }
  if (channels_.size() >= 0xFFFE) return Error{"too many channels (max 65534)"};
  ChannelRecord channel{static_cast<uint16_t>(channels_.size() + 1), schema_id, std::string(topic),
                        std::string(message_encoding), metadata};
  scratch_.clear();
  append_channel(scratch_, channel);
  if (auto err = emit(scratch_); !err) return Error{err.error()};
  channels_.push_back(std::move(channel));
  return channels_.back().id;
}

Status McapWriter::write(const MessageView& message) {
  if (auto err = check_writable(); !err) return err;
  if (message.channel_id == 0 || message.channel_id > channels_.size()) {
    return Error{"message on unknown channel " + std::to_string(message.channel_id)};
  }
  if (chunk_messages_ == 0) chunk_start_ns_ = chunk_end_ns_ = message.log_time_ns;
  chunk_start_ns_ = std::min(chunk_start_ns_, message.log_time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, message.log_time_ns);
  chunk_index_[message.channel_id].emplace_back(message.log_time_ns, chunk_records_.size());
  append_message(chunk_records_, message);
  ++chunk_messages_;

  auto& s = statistics_;
  if (s.message_count == 0) s.message_start_time_ns = s.message_end_time_ns = message.log_time_ns;
  s.message_start_time_ns = std::min(s.message_start_time_ns, message.log_time_ns);
  s.message_end_time_ns = std::max(s.message_end_time_ns, message.log_time_ns);
  ++s.message_count;
  ++s.channel_message_counts[message.channel_id];
  ++stats_.messages;
  stats_.message_bytes += message.data.size();

  if (chunk_records_.size() >= params_.chunk_size_bytes) return finish_chunk();
  return {};
}

Status McapWriter::flush_chunk() {
  if (auto err = check_writable(); !err) return err;
  return finish_chunk();
}

Status McapWriter::finish_chunk() {
  if (chunk_messages_ == 0) return {};
  const uint32_t crc = params_.chunk_crc ? crc32(chunk_records_) : 0;
  const bool zstd = params_.compression == Compression::kZstd;

  scratch_.clear();
  scratch_.reserve(encoded_chunk_bound(chunk_records_.size()));
  ByteWriter w(scratch_);
  w.u8(static_cast<uint8_t>(Opcode::kChunk));
  w.u64(0);
  w.u64(chunk_start_ns_);
  w.u64(chunk_end_ns_);
  w.u64(chunk_records_.size());
  w.u32(crc);
  w.str(zstd ? "zstd" : "");
  const size_t records_length_pos = scratch_.size();
  w.u64(0);
  const size_t records_start = scratch_.size();
  if (zstd) {
    if (auto err = compressor_->compress(chunk_records_, scratch_); !err) return err;
  } else {
    w.bytes(chunk_records_);
  }
  const uint64_t compressed_size = scratch_.size() - records_start;
  w.patch_u64(records_length_pos, compressed_size);
  w.patch_u64(1, scratch_.size() - kRecordPrefixBytes);

  ChunkIndexRecord index;
  index.message_start_time_ns = chunk_start_ns_;
  index.message_end_time_ns = chunk_end_ns_;
  index.chunk_start_offset = position_;
  index.chunk_length = scratch_.size();
  index.compression = zstd ? "zstd" : "";
  index.compressed_size = compressed_size;
  index.uncompressed_size = chunk_records_.size();
  if (auto err = emit(scratch_); !err) return err;

  // Message indexes, one per channel, written as one block right after the chunk.
  scratch_.clear();
  const uint64_t indexes_start = position_;
  for (auto& [channel, entries] : chunk_index_) {
    index.message_index_offsets[channel] = indexes_start + scratch_.size();
    // Stable sort: readers expect log-time order; ties keep arrival order.
    std::stable_sort(entries.begin(), entries.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    append_message_index(scratch_, MessageIndexRecord{channel, std::move(entries)});
  }
  index.message_index_length = scratch_.size();
  if (auto err = emit(scratch_); !err) return err;
  if (auto err = sink_->flush(); !err) {
    failure_ = Error{"flush failed: " + err.error()};
    return failure_;
  }

  append_chunk_index(chunk_indexes_, index);
  ++chunk_count_;
  ++stats_.chunks;
  chunk_records_.clear();
  chunk_index_.clear();
  chunk_messages_ = 0;
  if (index_spill_ != nullptr && chunk_indexes_.size() >= kIndexBlockBytes) {
    return spill_chunk_indexes();
  }
  return {};
}

size_t McapWriter::encoded_chunk_bound(size_t records_bytes) const {
  const size_t header = 64;
  return header +
         (params_.compression == Compression::kZstd ? zstd_bound(records_bytes) : records_bytes);
}

uint64_t McapWriter::buffer_bytes() const {
  return chunk_records_.capacity() + scratch_.capacity() + chunk_indexes_.capacity();
}

Status McapWriter::spill_chunk_indexes() {
  if (chunk_indexes_.empty()) return {};
  if (auto err = index_spill_->write(chunk_indexes_); !err) {
    failure_ = Error{"spilling chunk indexes failed: " + err.error()};
    return failure_;
  }
  spilled_index_bytes_ += chunk_indexes_.size();
  chunk_indexes_.clear();
  return {};
}

// Emits every ChunkIndex record (spilled ones first, in blocks through scratch_) as part of
// the summary, adding them to its CRC.
Status McapWriter::emit_chunk_indexes(Crc32& summary_crc) {
  for (uint64_t at = 0; at < spilled_index_bytes_;) {
    const uint64_t n = std::min<uint64_t>(kIndexBlockBytes, spilled_index_bytes_ - at);
    scratch_.resize(n);
    if (auto err = index_spill_->read(index_spill_base_ + at, scratch_); !err) {
      failure_ = Error{"reading spilled chunk indexes failed: " + err.error()};
      return failure_;
    }
    summary_crc.update(scratch_);
    if (auto err = emit(scratch_); !err) return err;
    at += n;
  }
  summary_crc.update(chunk_indexes_);
  return emit(chunk_indexes_);
}

Status McapWriter::close() {
  if (auto err = check_writable(); !err) return err;
  if (auto err = finish_chunk(); !err) return err;
  if (auto err = write_summary_and_footer(); !err) return err;
  closed_ = true;
  if (auto err = sink_->flush(); !err) {
    failure_ = Error{"flush failed: " + err.error()};
    return failure_;
  }
  return {};
}

Status McapWriter::write_summary_and_footer() {
  scratch_.clear();
  append_data_end(scratch_, params_.data_section_crc ? data_crc_.value() : 0);
  if (auto err = emit(scratch_); !err) return err;

  const uint64_t summary_start = position_;
  // The summary before the chunk indexes, the chunk indexes (streamed from the spill), then
  // the summary offsets and the footer; the CRC runs over all three.
  std::vector<uint8_t> summary;
  std::vector<SummaryOffsetRecord> groups;
  // Appends one group of same-opcode records and remembers where it is.
  auto group = [&](Opcode op, auto&& append_all) {
    const size_t begin = summary.size();
    append_all();
    if (summary.size() > begin) {
      groups.push_back({static_cast<uint8_t>(op), summary_start + begin, summary.size() - begin});
    }
  };
  group(Opcode::kSchema, [&] {
    for (const auto& s : schemas_) append_schema(summary, s);
  });
  group(Opcode::kChannel, [&] {
    for (const auto& c : channels_) append_channel(summary, c);
  });
  statistics_.schema_count = static_cast<uint16_t>(schemas_.size());
  statistics_.channel_count = static_cast<uint32_t>(channels_.size());
  statistics_.chunk_count = chunk_count_;
  group(Opcode::kStatistics, [&] { append_statistics(summary, statistics_); });
  const uint64_t index_bytes = spilled_index_bytes_ + chunk_indexes_.size();
  if (index_bytes > 0) {
    groups.push_back(
        {static_cast<uint8_t>(Opcode::kChunkIndex), summary_start + summary.size(), index_bytes});
  }
  Crc32 crc;
  crc.update(summary);
  if (auto err = emit(summary); !err) return err;
  if (auto err = emit_chunk_indexes(crc); !err) return err;

  std::vector<uint8_t> tail;
  const uint64_t summary_offset_start = position_;
  for (const auto& g : groups) append_summary_offset(tail, g);
  append_footer(tail, FooterRecord{summary_start, summary_offset_start, 0});
  // The summary CRC covers everything from summary_start through the footer's
  // summary_offset_start field, i.e. all but the 4 CRC bytes just appended.
  const size_t crc_pos = tail.size() - 4;
  crc.update(std::span(tail).first(crc_pos));
  ByteWriter(tail).patch_u32(crc_pos, crc.value());
  tail.insert(tail.end(), kMagic.begin(), kMagic.end());
  return emit(tail);
}

}  // namespace stereoball::recorder
