#pragma once
// Little-endian encoding and bounds-checked decoding of MCAP primitive types.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace stereoball::recorder {

/// Appends MCAP primitives (little-endian integers, length-prefixed strings) to a byte vector.
class ByteWriter {
 public:
  /// Writes into out (appending; out must outlive the writer).
  explicit ByteWriter(std::vector<uint8_t>& out) : out_(out) {}
  void u8(uint8_t v) { out_.push_back(v); }
  void u16(uint16_t v) { le(v, 2); }
  void u32(uint32_t v) { le(v, 4); }
  void u64(uint64_t v) { le(v, 8); }
  /// uint32 byte length followed by the bytes.
  void str(std::string_view s);
  /// Raw bytes, no prefix.
  void bytes(std::span<const uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }
  /// Overwrites 8 bytes at pos with v (patching a length written earlier).
  void patch_u64(size_t pos, uint64_t v);
  /// Overwrites 4 bytes at pos with v.
  void patch_u32(size_t pos, uint32_t v);
  /// Current size of the output.
  size_t size() const { return out_.size(); }

 private:
  void le(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t>& out_;
};

/// Reads MCAP primitives from a span; every read fails (returns nullopt) past the end.
class ByteReader {
 public:
  /// Reads from bytes (not owned).
  explicit ByteReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  std::optional<uint8_t> u8();
  std::optional<uint16_t> u16();
  std::optional<uint32_t> u32();
  std::optional<uint64_t> u64();
  /// uint32-length-prefixed string.
  std::optional<std::string> str();
  /// uint32-length-prefixed bytes (a view into the input).
  std::optional<std::span<const uint8_t>> bytes32();
  /// uint64-length-prefixed bytes (a view into the input).
  std::optional<std::span<const uint8_t>> bytes64();
  /// Exactly n bytes (a view into the input).
  std::optional<std::span<const uint8_t>> take(uint64_t n);
  /// Everything not read yet.
  std::span<const uint8_t> rest() const { return bytes_.subspan(pos_); }
  /// Bytes not read yet.
  size_t remaining() const { return bytes_.size() - pos_; }

 private:
  std::optional<uint64_t> le(int n);
  std::span<const uint8_t> bytes_;
  size_t pos_ = 0;
};

/// Little-endian uint64 at p (p must hold 8 bytes).
uint64_t load_u64(const uint8_t* p);

}  // namespace stereoball::recorder
