#pragma once
// Test helpers: deterministic multi-channel recordings written with McapWriter into memory.

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "recorder/core/reader.hpp"
#include "recorder/core/writer.hpp"

namespace stereoball::recorder::testing {

/// One message as the test wrote it (owning its payload).
struct StoredMessage {
  uint16_t channel_id = 0;
  uint32_t sequence = 0;
  uint64_t log_time_ns = 0;
  uint64_t publish_time_ns = 0;
  std::vector<uint8_t> data;
  bool operator==(const StoredMessage&) const = default;
};

/// A finished recording: file bytes, what went in, and how many messages each chunk closed on.
struct Recording {
  std::vector<uint8_t> bytes;
  std::vector<StoredMessage> messages;
  std::vector<uint64_t> messages_after_chunk;  ///< messages written when chunk i was completed
};

/// Copies a message view into an owning StoredMessage.
inline StoredMessage store(const MessageView& m) {
  return {m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns,
          std::vector<uint8_t>(m.data.begin(), m.data.end())};
}

/// Reads every message of an opened reader into owning copies, appended to out.
inline Status read_all(McapReader& reader, std::vector<StoredMessage>& out) {
  return reader.for_each_message([&](const MessageView& m) {
    out.push_back(store(m));
    return true;
  });
}

/// Writes count messages round-robin-ish over channels topics (random sizes up to max_bytes),
/// the chunk indexes spilled to index_spill when one is given.
inline Recording make_recording(const WriterParams& params, int channels, int count,
                                size_t max_bytes, uint32_t seed = 1, Spill* index_spill = nullptr) {
  Recording rec;
  MemorySink sink;
  McapWriter writer(params);
  if (!writer.open(sink, index_spill).ok()) return rec;
  const auto schema = writer.add_schema("test::Msg", "omgidl", std::string_view("struct Msg {};"));
  std::vector<uint16_t> ids;
  for (int c = 0; c < channels; ++c) {
    ids.push_back(writer.add_channel(schema.value(), "topic/" + std::to_string(c), "cdr").value());
  }
  std::mt19937 rng(seed);
  uint64_t t = 1'700'000'000'000'000'000ull;
  for (int i = 0; i < count; ++i) {
    StoredMessage m;
    m.channel_id = ids[rng() % ids.size()];
    m.sequence = static_cast<uint32_t>(i);
    t += 1'000'000 + rng() % 1'000'000;
    m.log_time_ns = t;
    m.publish_time_ns = t - 500'000;
    m.data.resize(rng() % (max_bytes + 1));
    // Half random, half repeated bytes: compressible like real data, but not trivially.
    for (size_t b = 0; b < m.data.size(); ++b) {
      m.data[b] = b % 2 ? static_cast<uint8_t>(rng()) : static_cast<uint8_t>(b / 64);
    }
    const uint64_t chunks_before = writer.stats().chunks;
    if (!writer.write({m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns, m.data}).ok()) {
      return rec;
    }
    rec.messages.push_back(std::move(m));
    if (writer.stats().chunks != chunks_before) rec.messages_after_chunk.push_back(i + 1);
  }
  const uint64_t chunks_before = writer.stats().chunks;
  if (!writer.close().ok()) return rec;
  if (writer.stats().chunks != chunks_before) rec.messages_after_chunk.push_back(count);
  rec.bytes = sink.bytes();
  return rec;
}

/// Every message the reader yields for bytes (empty when open fails).
inline std::vector<StoredMessage> read_all(const std::vector<uint8_t>& bytes,
                                           std::vector<std::string>* notes = nullptr) {
  MemorySource source(bytes);
  McapReader reader(source);
  std::vector<StoredMessage> out;
  if (!reader.open().ok()) return out;
  reader.for_each_message([&](const MessageView& m) {
    out.push_back(store(m));
    return true;
  });
  if (notes) *notes = reader.notes();
  return out;
}

}  // namespace stereoball::recorder::testing
