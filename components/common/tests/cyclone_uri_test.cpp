#include "common/util/cyclone_uri.hpp"

#include <gtest/gtest.h>

#include <map>

namespace stereoball::util {
namespace {

std::optional<std::string> fake_read(const std::string& path) {
  static const std::map<std::string, std::string> files{{"/cfg/a.xml", "<A/>"},
                                                        {"/cfg/b.xml", "<B/>"}};
  const auto it = files.find(path);
  if (it == files.end()) return std::nullopt;
  return it->second;
}

TEST(CycloneUriEntries, FileUrisPlainPathsAndInlineXmlInOrder) {
  // Given a value with every kind of entry, spaces and a blank entry
  // When it is split
  const auto entries = cyclone_uri_entries("file:///cfg/a.xml, /cfg/b.xml,,  <Inline/>", fake_read);
  // Then each entry keeps its order, its source name and its text
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].source, "/cfg/a.xml");
  EXPECT_EQ(entries[0].xml, "<A/>");
  EXPECT_EQ(entries[1].source, "/cfg/b.xml");
  EXPECT_EQ(entries[1].xml, "<B/>");
  EXPECT_EQ(entries[2].source, "inline configuration");
  EXPECT_EQ(entries[2].xml, "<Inline/>");
}

TEST(CycloneUriEntries, UnreadableFileIsKeptWithoutText) {
  // Given a missing file between two readable ones
  const auto entries = cyclone_uri_entries("file:///missing.xml", fake_read);
  // Then the caller sees which file could not be read
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].source, "/missing.xml");
  EXPECT_FALSE(entries[0].xml.has_value());
}

TEST(CycloneUriEntries, EmptyValueHasNoEntries) {
  EXPECT_TRUE(cyclone_uri_entries("", fake_read).empty());
  EXPECT_TRUE(cyclone_uri_entries(" ,\t, ", fake_read).empty());
}

TEST(ReadTextFile, MissingFileIsNullopt) {
  EXPECT_FALSE(read_text_file("/nonexistent/stereoball/cyclone.xml").has_value());
}

}  // namespace
}  // namespace stereoball::util
