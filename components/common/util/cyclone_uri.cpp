#include "common/util/cyclone_uri.hpp"

#include <fstream>
#include <sstream>

namespace stereoball::util {

std::vector<CycloneUriEntry> cyclone_uri_entries(const std::string& uri,
                                                 const ReadText& read_file) {
  std::vector<CycloneUriEntry> entries;
  std::stringstream list(uri);
  std::string entry;
  while (std::getline(list, entry, ',')) {
    const auto start = entry.find_first_not_of(" \t\n");
    if (start == std::string::npos) continue;
    entry = entry.substr(start);
    if (entry[0] == '<') {
      entries.push_back({"inline configuration", entry});
      continue;
    }
    std::string path = entry.rfind("file://", 0) == 0 ? entry.substr(7) : entry;
    std::optional<std::string> xml = read_file(path);
    entries.push_back({std::move(path), std::move(xml)});
  }
  return entries;
}

std::optional<std::string> read_text_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace stereoball::util
