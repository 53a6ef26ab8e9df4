#include "recorder/core/byte_io.hpp"

namespace stereoball::recorder {

void ByteWriter::str(std::string_view s) {
  u32(static_cast<uint32_t>(s.size()));
  out_.insert(out_.end(), s.begin(), s.end());
}

void ByteWriter::patch_u64(size_t pos, uint64_t v) {
  for (int i = 0; i < 8; ++i) out_[pos + i] = static_cast<uint8_t>(v >> (8 * i));
}

void ByteWriter::patch_u32(size_t pos, uint32_t v) {
  for (int i = 0; i < 4; ++i) out_[pos + i] = static_cast<uint8_t>(v >> (8 * i));
}

std::optional<uint64_t> ByteReader::le(int n) {
  if (remaining() < static_cast<size_t>(n)) return std::nullopt;
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t{bytes_[pos_ + i]} << (8 * i);
  pos_ += n;
  return v;
}

std::optional<uint8_t> ByteReader::u8() {
  auto v = le(1);
  if (!v) return std::nullopt;
  return static_cast<uint8_t>(*v);
}

std::optional<uint16_t> ByteReader::u16() {
  auto v = le(2);
  if (!v) return std::nullopt;
  return static_cast<uint16_t>(*v);
}

std::optional<uint32_t> ByteReader::u32() {
  auto v = le(4);
  if (!v) return std::nullopt;
  return static_cast<uint32_t>(*v);
}

std::optional<uint64_t> ByteReader::u64() {
  return le(8);
}

std::optional<std::span<const uint8_t>> ByteReader::take(uint64_t n) {
  if (n > remaining()) return std::nullopt;
  auto out = bytes_.subspan(pos_, n);
  pos_ += n;
  return out;
}

std::optional<std::string> ByteReader::str() {
  auto b = bytes32();
  if (!b) return std::nullopt;
  return std::string(reinterpret_cast<const char*>(b->data()), b->size());
}

std::optional<std::span<const uint8_t>> ByteReader::bytes32() {
  auto n = u32();
  if (!n) return std::nullopt;
  return take(*n);
}

std::optional<std::span<const uint8_t>> ByteReader::bytes64() {
  auto n = u64();
  if (!n) return std::nullopt;
  return take(*n);
}

uint64_t load_u64(const uint8_t* p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= uint64_t{p[i]} << (8 * i);
  return v;
}

}  // namespace stereoball::recorder
