// The one JSON string escaping of the tools that write JSON by hand.
#include "common/util/json_text.hpp"

#include <gtest/gtest.h>

namespace stereoball::util {
namespace {

TEST(JsonText, QuotesBackslashesAndControlCharactersAreEscaped) {
  // Given text with a quote, a backslash, a newline, a tab and another control character
  const std::string text = std::string("say \"hi\"\\\n\tend") + '\x01';
  // When it is escaped
  // Then each stands as JSON requires, and plain text is unchanged
  EXPECT_EQ(json_escape(text), "say \\\"hi\\\"\\\\\\n\\tend\\u0001");
  EXPECT_EQ(json_escape("plain: ü"), "plain: ü");
}

TEST(JsonText, QuotedAddsTheQuotes) {
  // Given text with a quote
  // When it is quoted
  // Then it is a whole JSON string
  EXPECT_EQ(json_quoted("a\"b"), "\"a\\\"b\"");
  EXPECT_EQ(json_quoted(""), "\"\"");
}

}  // namespace
}  // namespace stereoball::util
