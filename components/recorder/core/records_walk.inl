#pragma once
// Template body of walk_records (included by records.hpp).

#include "recorder/core/byte_io.hpp"

namespace stereoball::recorder {

template <class F>
std::optional<RecordWalkStop> walk_records(std::span<const uint8_t> buffer, F&& f) {
  uint64_t pos = 0;
  while (pos < buffer.size()) {
    const uint64_t left = buffer.size() - pos;
    if (left < kRecordPrefixBytes) {
      return RecordWalkStop{pos, "truncated record prefix (" + std::to_string(left) + " bytes)"};
    }
    const uint64_t length = load_u64(buffer.data() + pos + 1);
    if (length > left - kRecordPrefixBytes) {
      return RecordWalkStop{pos, "record length " + std::to_string(length) + " exceeds the " +
                                     std::to_string(left - kRecordPrefixBytes) + " bytes left"};
    }
    RecordView record{buffer[pos], buffer.subspan(pos + kRecordPrefixBytes, length)};
    if (!f(pos, record)) return std::nullopt;
    pos += kRecordPrefixBytes + length;
  }
  return std::nullopt;
}

}  // namespace stereoball::recorder
