#pragma once
// The entries of a CYCLONEDDS_URI value, as Cyclone reads them: comma-separated file:// URIs,
// plain paths or inline XML, a later entry overriding an earlier one. Pure: the caller passes
// the file reader, so tests need no files.

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace stereoball::util {

/// One entry of a CYCLONEDDS_URI value.
struct CycloneUriEntry {
  std::string source;              ///< the file's path, or "inline configuration"
  std::optional<std::string> xml;  ///< its XML text; nullopt when the file cannot be read
};

/// Reads a file's whole text; nullopt when it cannot be read.
using ReadText = std::function<std::optional<std::string>(const std::string& path)>;

/// The entries of uri in order (blank entries skipped), each with its XML from read_file.
std::vector<CycloneUriEntry> cyclone_uri_entries(const std::string& uri, const ReadText& read_file);

/// A file's whole text from disk; nullopt when it cannot be opened.
std::optional<std::string> read_text_file(const std::string& path);

}  // namespace stereoball::util
