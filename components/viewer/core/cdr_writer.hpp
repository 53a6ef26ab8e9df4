#pragma once
// Little-endian plain CDR (XCDR1, encapsulation CDR_LE) for the derived Foxglove messages:
// primitives aligned to their size (at most 8) relative to the payload start, strings with
// length and NUL, sequences with a uint32 count.

#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <string_view>
#include <vector>

namespace stereoball::viewer {

/// Appends CDR-encoded values to a byte buffer that starts with the encapsulation header.
class CdrWriter {
 public:
  CdrWriter() : bytes_{0x00, 0x01, 0x00, 0x00} {}

  void u8(uint8_t v) { put(v); }
  void boolean(bool v) { put(static_cast<uint8_t>(v ? 1 : 0)); }
  void u32(uint32_t v) { put(v); }
  void i32(int32_t v) { put(v); }
  void f64(double v) { put(v); }
  /// string: uint32 length including the terminating NUL, the bytes, the NUL.
  void string(std::string_view s) {
    u32(static_cast<uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
  }
  /// sequence<uint8>: count then the bytes.
  void byte_sequence(std::span<const uint8_t> data) {
    u32(static_cast<uint32_t>(data.size()));
    bytes_.insert(bytes_.end(), data.begin(), data.end());
  }
  /// Count of a sequence whose elements the caller writes next.
  void sequence_length(size_t n) { u32(static_cast<uint32_t>(n)); }

  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t> take() { return std::move(bytes_); }

 private:
  static constexpr size_t kHeader = 4;
  template <typename T>
  void put(T v) {
    static_assert(std::endian::native == std::endian::little, "CDR_LE writer needs a LE host");
    const size_t align = sizeof(T);
    while ((bytes_.size() - kHeader) % align != 0) bytes_.push_back(0);
    const size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &v, sizeof(T));
  }
  std::vector<uint8_t> bytes_;
};

}  // namespace stereoball::viewer
