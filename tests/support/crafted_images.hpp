#pragma once
// Test support: crafted image headers, as an attacker writes them (issue 22: a small JPEG or
// PNG whose header claims 20000x20000).

#include <cstdint>
#include <vector>

namespace stereoball::testing {

/// Rewrites the size a baseline JPEG (SOF0 marker) or a PNG (IHDR chunk, CRC left stale)
/// claims, leaving the compressed data as it is. False when bytes hold neither.
inline bool claim_image_size(std::vector<uint8_t>& bytes, int width_px, int height_px) {
  if (bytes.size() >= 24 && bytes[0] == 0x89) {
    for (int i = 0; i < 4; ++i) {
      bytes[16 + i] = static_cast<uint8_t>(static_cast<uint32_t>(width_px) >> (24 - 8 * i));
      bytes[20 + i] = static_cast<uint8_t>(static_cast<uint32_t>(height_px) >> (24 - 8 * i));
    }
    return true;
  }
  for (size_t i = 2; i + 9 < bytes.size(); ++i) {
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xC0) {
      bytes[i + 5] = static_cast<uint8_t>(height_px >> 8);
      bytes[i + 6] = static_cast<uint8_t>(height_px);
      bytes[i + 7] = static_cast<uint8_t>(width_px >> 8);
      bytes[i + 8] = static_cast<uint8_t>(width_px);
      return true;
    }
  }
  return false;
}

}  // namespace stereoball::testing
