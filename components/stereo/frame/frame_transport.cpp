#include "stereo/frame/frame_transport.hpp"

#include "common/util/cyclone_uri.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <regex>

namespace stereoball::stereo {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// Cyclone's and the kernel's units: MiB.
std::string mib_text(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

// The request of one XML document: the max attribute of its last SocketReceiveBufferSize,
// else its min attribute.
std::optional<uint64_t> receive_buffer_in(const std::string& xml) {
  static const std::regex element(R"(<SocketReceiveBufferSize\b([^>]*)>)", std::regex::icase);
  static const std::regex max_attr(R"re(\bmax\s*=\s*"([^"]*)")re", std::regex::icase);
  static const std::regex min_attr(R"re(\bmin\s*=\s*"([^"]*)")re", std::regex::icase);
  std::optional<uint64_t> request;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), element);
       it != std::sregex_iterator(); ++it) {
    const std::string attributes = (*it)[1].str();
    std::smatch m;
    std::optional<uint64_t> value;
    if (std::regex_search(attributes, m, max_attr)) value = parse_cyclone_size(m[1].str());
    if (!value && std::regex_search(attributes, m, min_attr)) value = parse_cyclone_size(m[1]);
    if (value) request = value;
  }
  return request;
}

}  // namespace

uint64_t TransportLimits::receive_buffer_bytes() const {
  return rmem_max_bytes == 0 ? requested_bytes : std::min(requested_bytes, rmem_max_bytes);
}

std::optional<uint64_t> parse_cyclone_size(const std::string& text) {
  size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  size_t digits = i;
  while (digits < text.size() && std::isdigit(static_cast<unsigned char>(text[digits]))) ++digits;
  if (digits == i || digits - i > 15) return std::nullopt;
  const uint64_t number = std::strtoull(text.substr(i, digits - i).c_str(), nullptr, 10);
  std::string unit = lower(text.substr(digits));
  unit.erase(std::remove_if(unit.begin(), unit.end(),
                            [](unsigned char c) { return std::isspace(c) != 0; }),
             unit.end());
  if (unit.empty() || unit == "b") return number;
  if (unit == "kb" || unit == "kib") return number << 10;
  if (unit == "mb" || unit == "mib") return number << 20;
  if (unit == "gb" || unit == "gib") return number << 30;
  return std::nullopt;
}

std::optional<std::pair<uint64_t, std::string>> configured_receive_buffer(
    const std::string& uri,
    const std::function<std::optional<std::string>(const std::string&)>& read_file) {
  std::optional<std::pair<uint64_t, std::string>> found;
  for (const util::CycloneUriEntry& entry : util::cyclone_uri_entries(uri, read_file)) {
    if (!entry.xml) continue;
    if (const auto bytes = receive_buffer_in(*entry.xml)) found.emplace(*bytes, entry.source);
  }
  return found;
}

TransportLimits read_transport_limits(const CycloneSetup& setup) {
  TransportLimits limits;
  limits.shared_memory = setup.shared_memory && setup.built_in_xml.empty();
  limits.keyless = !setup.built_in_xml.empty();
  if (limits.keyless) {
    if (const auto bytes = receive_buffer_in(setup.built_in_xml)) {
      limits.requested_bytes = *bytes;
      limits.requested_from =
          "the built-in loopback-only configuration (no deployment key; CYCLONEDDS_URI unused)";
    }
  } else if (const char* uri = std::getenv("CYCLONEDDS_URI")) {
    if (auto request = configured_receive_buffer(uri, util::read_text_file)) {
      limits.requested_bytes = request->first;
      limits.requested_from = "SocketReceiveBufferSize in " + request->second;
    }
  }
  if (auto text = util::read_text_file("/proc/sys/net/core/rmem_max")) {
    limits.rmem_max_bytes = std::strtoull(text->c_str(), nullptr, 10);
  }
  return limits;
}

uint64_t frame_sample_bytes(uint64_t left_bytes, uint64_t right_bytes) {
  // seq, stamps, sizes, the source and encoding strings and the CDR header: well under 1 KB.
  constexpr uint64_t kFields = 1024;
  return left_bytes + right_bytes + kFields;
}

std::optional<std::string> oversize_warning(uint64_t sample_bytes, const TransportLimits& limits,
                                            const std::string& what) {
  if (limits.shared_memory || sample_bytes <= limits.capacity_bytes()) return std::nullopt;
  std::string line = what + ": each stereo/frame sample is " + mib_text(sample_bytes) +
                     " but a reader's socket takes about " + mib_text(limits.capacity_bytes()) +
                     " at once (twice its " + mib_text(limits.receive_buffer_bytes()) +
                     " receive buffer: " + limits.requested_from + " asks " +
                     mib_text(limits.requested_bytes);
  if (limits.rmem_max_bytes != 0) {
    line += ", the kernel caps it at net.core.rmem_max = " + std::to_string(limits.rmem_max_bytes);
  }
  return line + "): most frames will be lost in transport. " +
         transport_remedies(sample_bytes, limits.keyless);
}

std::string transport_remedies(uint64_t sample_bytes, bool keyless) {
  std::string text =
      "Remedies: frame_encoding: jpeg (camera_server config or --frame-encoding jpeg); a lower "
      "publish_width_px; ";
  if (keyless) {
    return text + "or raise net.core.rmem_max to at least " + std::to_string(sample_bytes) +
           " (deploy/systemd/90-stereoball-net.conf, sysctl --system). Without a deployment key "
           "this process runs on the built-in loopback-only configuration and ignores "
           "CYCLONEDDS_URI, so shared memory and a larger SocketReceiveBufferSize need a key "
           "('stereoball keys init', STEREOBALL_KEY_FILE)";
  }
  return text +
         "shared memory on one host (CYCLONEDDS_URI=config/cyclonedds/shm.xml with iox-roudi -c "
         "config/iceoryx/roudi.toml, whose largest mempool must hold the sample); or raise "
         "net.core.rmem_max to at least " +
         std::to_string(sample_bytes) +
         " (deploy/systemd/90-stereoball-net.conf, sysctl --system) with a SocketReceiveBufferSize "
         "max at least that large in the Cyclone configuration";
}

}  // namespace stereoball::stereo
