#include "viewer/core/pair_message.hpp"

#include <bit>
#include <cstring>

namespace stereoball::viewer {
namespace {

template <typename T>
void put(std::string& out, size_t at, T value) {
  std::memcpy(out.data() + at, &value, sizeof value);
}

template <typename T>
T get(std::span<const uint8_t> in, size_t at) {
  T value;
  std::memcpy(&value, in.data() + at, sizeof value);
  return value;
}

}  // namespace

// x86-64 and aarch64 Linux are little-endian, the byte order the page's DataView reads.
static_assert(std::endian::native == std::endian::little);

std::string pair_message(const PairHeader& header, std::span<const uint8_t> left_jpeg,
                         std::span<const uint8_t> right_jpeg) {
  std::string out(kPairHeaderBytes + left_jpeg.size() + right_jpeg.size(), '\0');
  put(out, 0, kPairMessageType);
  put(out, 4, static_cast<uint32_t>(left_jpeg.size()));
  put(out, 8, static_cast<double>(header.frame_seq));
  put(out, 16, header.capture_ms);
  put(out, 24, header.source_width_px);
  put(out, 28, header.source_height_px);
  put(out, 32, header.received_ms);
  put(out, 40, header.encoded_ms);
  if (!left_jpeg.empty())
    std::memcpy(out.data() + kPairHeaderBytes, left_jpeg.data(), left_jpeg.size());
  if (!right_jpeg.empty())
    std::memcpy(out.data() + kPairHeaderBytes + left_jpeg.size(), right_jpeg.data(),
                right_jpeg.size());
  return out;
}

std::optional<PairHeader> parse_pair_header(std::span<const uint8_t> message) {
  if (message.size() < kPairHeaderBytes || get<uint32_t>(message, 0) != kPairMessageType)
    return std::nullopt;
  PairHeader h;
  h.left_bytes = get<uint32_t>(message, 4);
  if (h.left_bytes > message.size() - kPairHeaderBytes) return std::nullopt;
  h.frame_seq = static_cast<uint64_t>(get<double>(message, 8));
  h.capture_ms = get<double>(message, 16);
  h.source_width_px = get<uint32_t>(message, 24);
  h.source_height_px = get<uint32_t>(message, 28);
  h.received_ms = get<double>(message, 32);
  h.encoded_ms = get<double>(message, 40);
  return h;
}

}  // namespace stereoball::viewer
