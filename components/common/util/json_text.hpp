#pragma once
// Text inside a JSON string: the one escaping every tool that writes JSON by hand uses.

#include <cstdio>
#include <string>
#include <string_view>

namespace stereoball::util {

/// TEXT with `"` and `\` escaped, newline and tab as `\n` and `\t`, other control characters
/// as `\u00XX`: ready to stand between the quotes of a JSON string.
inline std::string json_escape(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\u%04x",
                    static_cast<unsigned>(static_cast<unsigned char>(c)));
      out += buf;
    } else {
      out += c;
    }
  }
  return out;
}

/// TEXT as a JSON string, quotes included.
inline std::string json_quoted(std::string_view text) {
  return "\"" + json_escape(text) + "\"";
}

}  // namespace stereoball::util
