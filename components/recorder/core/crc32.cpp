#include "recorder/core/crc32.hpp"

#include <array>
#include <cstring>

#ifdef SB_RECORDER_HAVE_ZLIB
#include <zlib.h>
#endif

namespace stereoball::recorder {
namespace {

constexpr uint32_t kPolynomial = 0xEDB88320u;

// Slicing-by-8 tables: table[k][b] is the CRC contribution of byte b followed by k zero bytes.
using Tables = std::array<std::array<uint32_t, 256>, 8>;

constexpr Tables make_tables() {
  Tables t{};
  for (uint32_t b = 0; b < 256; ++b) {
    uint32_t c = b;
    for (int i = 0; i < 8; ++i) c = (c & 1u) ? (c >> 1) ^ kPolynomial : c >> 1;
    t[0][b] = c;
  }
  for (uint32_t b = 0; b < 256; ++b) {
    for (size_t k = 1; k < 8; ++k) t[k][b] = (t[k - 1][b] >> 8) ^ t[0][t[k - 1][b] & 0xFFu];
  }
  return t;
}

constexpr Tables kTables = make_tables();

uint32_t load_le32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

// Advances a raw (pre-inverted) CRC state over bytes with the slicing-by-8 tables.
uint32_t table_update(uint32_t state, std::span<const uint8_t> bytes) {
  const uint8_t* p = bytes.data();
  size_t n = bytes.size();
  uint32_t c = state;
  while (n >= 8) {
    const uint32_t lo = load_le32(p) ^ c;
    const uint32_t hi = load_le32(p + 4);
    c = kTables[7][lo & 0xFF] ^ kTables[6][(lo >> 8) & 0xFF] ^ kTables[5][(lo >> 16) & 0xFF] ^
        kTables[4][lo >> 24] ^ kTables[3][hi & 0xFF] ^ kTables[2][(hi >> 8) & 0xFF] ^
        kTables[1][(hi >> 16) & 0xFF] ^ kTables[0][hi >> 24];
    p += 8;
    n -= 8;
  }
  while (n-- > 0) c = kTables[0][(c ^ *p++) & 0xFF] ^ (c >> 8);
  return c;
}

}  // namespace

uint32_t crc32_portable(std::span<const uint8_t> bytes) {
  return table_update(0xFFFFFFFFu, bytes) ^ 0xFFFFFFFFu;
}

void Crc32::update(std::span<const uint8_t> bytes) {
  // zlib answers a null buffer with its initial value, which would drop what came before.
  if (bytes.empty()) return;
#ifdef SB_RECORDER_HAVE_ZLIB
  // zlib's braided CRC is about 3x faster than the portable tables; same polynomial.
  state_ = static_cast<uint32_t>(crc32_z(value(), bytes.data(), bytes.size())) ^ 0xFFFFFFFFu;
#else
  state_ = table_update(state_, bytes);
#endif
}

uint32_t crc32(std::span<const uint8_t> bytes) {
  Crc32 crc;
  crc.update(bytes);
  return crc.value();
}

}  // namespace stereoball::recorder
