#include <gtest/gtest.h>

#include <random>
#include <string>

#include "recorder/core/reader.hpp"
#include "recorder/core/test_support.hpp"

namespace stereoball::recorder {
namespace {

Status open_bytes(const std::vector<uint8_t>& bytes) {
  MemorySource source(bytes);
  McapReader reader(source);
  return reader.open();
}

std::vector<uint8_t> text(const std::string& s) {
  return {s.begin(), s.end()};
}

TEST(Garbage, GivenNonMcapInputsWhenOpenedThenTheErrorSaysBadMagic) {
  std::mt19937 rng(5);
  std::vector<uint8_t> random(5000);
  for (auto& b : random) b = static_cast<uint8_t>(rng());
  const std::vector<std::vector<uint8_t>> inputs = {text("hello, this is a text file\n"), random,
                                                    text("\x89PNG\r\n\x1a\n0000000000000"),
                                                    text("\x89MCA"), text("\x89MCAP1\r\n")};
  for (const auto& in : inputs) {
    const auto err = open_bytes(in);
    ASSERT_FALSE(err.ok());
    EXPECT_EQ(err.error(), "not an MCAP file: bad magic");
  }
}

TEST(Garbage, GivenAnEmptyFileWhenOpenedThenTheErrorSaysEmpty) {
  const auto err = open_bytes({});
  ASSERT_FALSE(err.ok());
  EXPECT_NE(err.error().find("empty"), std::string::npos);
}

TEST(Garbage, GivenMagicFollowedByGarbageWhenOpenedThenHeaderProblemIsNamed) {
  std::vector<uint8_t> bytes(kMagic.begin(), kMagic.end());
  for (int i = 0; i < 100; ++i) bytes.push_back(static_cast<uint8_t>(0x30 + i));
  const auto err = open_bytes(bytes);
  ASSERT_FALSE(err.ok());
  EXPECT_NE(err.error().find("Header"), std::string::npos) << err.error();
}

TEST(Garbage, GivenRandomBytesAfterAValidHeaderWhenReadThenNoMessagesAndAStopNote) {
  std::vector<uint8_t> bytes(kMagic.begin(), kMagic.end());
  append_header(bytes, HeaderRecord{"", "x"});
  std::mt19937 rng(9);
  for (int i = 0; i < 4000; ++i) bytes.push_back(static_cast<uint8_t>(rng()));
  std::vector<std::string> notes;
  EXPECT_TRUE(testing::read_all(bytes, &notes).empty());
  EXPECT_GE(notes.size(), 2u);  // no summary + where it stopped
}

TEST(Garbage, GivenRandomByteFlipsWhenReadThenEveryDeliveredMessageIsAnOriginal) {
  WriterParams p;
  p.chunk_size_bytes = 4096;
  const auto rec = testing::make_recording(p, 3, 150, 400, 21);
  std::mt19937 rng(77);
  for (int trial = 0; trial < 300; ++trial) {
    auto bytes = rec.bytes;
    const int flips = 1 + static_cast<int>(rng() % 3);
    for (int f = 0; f < flips; ++f) bytes[8 + rng() % (bytes.size() - 8)] ^= 1u << (rng() % 8);
    const auto got = testing::read_all(bytes);
    ASSERT_LE(got.size(), rec.messages.size());
    for (const auto& m : got) {
      ASSERT_LT(m.sequence, rec.messages.size());
      EXPECT_EQ(m.data, rec.messages[m.sequence].data) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace stereoball::recorder
