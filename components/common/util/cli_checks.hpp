#pragma once
// Command-line checks CLI11 does not have (header-only; the tools that include it link CLI11).

#include "common/util/cli11.hpp"

#include <cerrno>
#include <cstdlib>
#include <string>

namespace stereoball::cli {

/// A whole number that fits in 64 unsigned bits. CLI11 alone turns "-1" into 2^64 - 1 and
/// a number too large into 2^64 - 1 without a word: a seed or count given wrong would run
/// something else than asked.
inline CLI::Validator unsigned_64() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
          return "must be a whole number >= 0, got '" + text + "'";
        errno = 0;
        (void)std::strtoull(text.c_str(), nullptr, 10);
        if (errno == ERANGE) return "must be at most 18446744073709551615, got " + text;
        return {};
      },
      "UINT64");
}

}  // namespace stereoball::cli
