#include "recorder/core/crc32.hpp"

#include <gtest/gtest.h>

#include <random>
#include <string_view>
#include <vector>

namespace stereoball::recorder {
namespace {

std::span<const uint8_t> as_bytes(std::string_view s) {
  return {reinterpret_cast<const uint8_t*>(s.data()), s.size()};
}

TEST(Crc32, GivenTheStandardCheckInputWhenHashedThenMatchesTheCatalogueValue) {
  // CRC-32/ISO-HDLC check value from the CRC catalogue.
  EXPECT_EQ(crc32(as_bytes("123456789")), 0xCBF43926u);
  EXPECT_EQ(crc32({}), 0u);
}

TEST(Crc32, GivenRandomSplitsWhenHashedIncrementallyThenEqualsOneShot) {
  std::mt19937 rng(7);
  std::vector<uint8_t> data(10'000);
  for (auto& b : data) b = static_cast<uint8_t>(rng());
  const uint32_t whole = crc32(data);
  for (int trial = 0; trial < 20; ++trial) {
    Crc32 crc;
    size_t pos = 0;
    while (pos < data.size()) {
      const size_t n = std::min<size_t>(rng() % 37, data.size() - pos);
      crc.update(std::span(data).subspan(pos, n));
      pos += n;
    }
    EXPECT_EQ(crc.value(), whole);
  }
}

TEST(Crc32, GivenAnEmptyBufferWithNoStorageWhenAddedThenTheChecksumIsUnchanged) {
  // Given a running checksum, When an empty vector (null data) is added in the middle
  Crc32 crc;
  crc.update(as_bytes("1234"));
  crc.update(std::vector<uint8_t>{});
  crc.update(as_bytes("56789"));
  // Then it is the checksum of the bytes alone (zlib used to restart on a null buffer)
  EXPECT_EQ(crc.value(), 0xCBF43926u);
}

TEST(Crc32, GivenRandomBuffersWhenHashedByBothImplementationsThenTheyAgree) {
  std::mt19937 rng(3);
  for (size_t n : {0u, 1u, 7u, 8u, 9u, 63u, 1000u, 4097u}) {
    std::vector<uint8_t> data(n);
    for (auto& b : data) b = static_cast<uint8_t>(rng());
    EXPECT_EQ(crc32_portable(data), crc32(data)) << n;
  }
  EXPECT_EQ(crc32_portable(as_bytes("123456789")), 0xCBF43926u);
}

TEST(Crc32, GivenOneFlippedBitWhenHashedThenDiffers) {
  std::vector<uint8_t> data(1000, 0x5A);
  const uint32_t before = crc32(data);
  data[500] ^= 0x10;
  EXPECT_NE(crc32(data), before);
}

}  // namespace
}  // namespace stereoball::recorder
