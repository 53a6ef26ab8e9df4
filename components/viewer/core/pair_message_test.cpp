#include "viewer/core/pair_message.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stereoball::viewer {
namespace {

std::span<const uint8_t> bytes(const std::string& s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

TEST(PairMessage, HeaderAndBothJpegsReadBack) {
  // Given a header and two JPEGs of different sizes
  PairHeader h;
  h.frame_seq = 123456;
  h.capture_ms = 1'700'000'000'123.5;
  h.source_width_px = 1280;
  h.source_height_px = 960;
  h.received_ms = h.capture_ms + 2;
  h.encoded_ms = h.capture_ms + 6;
  const std::vector<uint8_t> left = {0xFF, 0xD8, 1, 2, 3}, right = {0xFF, 0xD8, 9};
  // When it becomes a message and is read back
  const std::string m = pair_message(h, left, right);
  const auto back = parse_pair_header(bytes(m));
  // Then every field is the same and the JPEGs follow the header, left first
  ASSERT_TRUE(back);
  EXPECT_EQ(back->frame_seq, h.frame_seq);
  EXPECT_EQ(back->capture_ms, h.capture_ms);
  EXPECT_EQ(back->source_width_px, 1280u);
  EXPECT_EQ(back->source_height_px, 960u);
  EXPECT_EQ(back->received_ms, h.received_ms);
  EXPECT_EQ(back->encoded_ms, h.encoded_ms);
  EXPECT_EQ(back->left_bytes, left.size());
  ASSERT_EQ(m.size(), kPairHeaderBytes + left.size() + right.size());
  EXPECT_EQ(static_cast<uint8_t>(m[kPairHeaderBytes + left.size()]), 0xFF);
  EXPECT_EQ(static_cast<uint8_t>(m.back()), 9);
}

TEST(PairMessage, OtherOrTruncatedMessagesAreRefused) {
  const std::vector<uint8_t> jpeg(10, 0xAB);
  std::string m = pair_message({}, jpeg, jpeg);
  EXPECT_FALSE(parse_pair_header(bytes(m.substr(0, kPairHeaderBytes - 1))));  // short header
  EXPECT_FALSE(parse_pair_header(bytes(m.substr(0, kPairHeaderBytes + 5))));  // left cut short
  m[0] = 1;
  EXPECT_FALSE(parse_pair_header(bytes(m)));  // the older type 1 layout
}

}  // namespace
}  // namespace stereoball::viewer
