#pragma once
// CRC-32 (IEEE 802.3, reflected polynomial 0xEDB88320), the checksum MCAP uses.

#include <cstddef>
#include <cstdint>
#include <span>

namespace stereoball::recorder {

/// Incremental CRC-32: feed bytes with update(), read the checksum with value().
class Crc32 {
 public:
  /// Adds bytes to the running checksum.
  void update(std::span<const uint8_t> bytes);
  /// The CRC-32 of every byte fed so far.
  uint32_t value() const { return state_ ^ 0xFFFFFFFFu; }

 private:
  uint32_t state_ = 0xFFFFFFFFu;
};

/// CRC-32 of one buffer.
uint32_t crc32(std::span<const uint8_t> bytes);

/// CRC-32 of one buffer with the built-in tables (used when zlib is absent; tests compare both).
uint32_t crc32_portable(std::span<const uint8_t> bytes);

}  // namespace stereoball::recorder
