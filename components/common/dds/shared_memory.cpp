#include "common/dds/shared_memory.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <mutex>
#include <regex>

#include "common/util/cyclone_uri.hpp"
#include "common/util/log.hpp"

namespace stereoball::dds {
namespace {

// RouDi's well-known socket (iceoryx 2.0: the "roudi" channel under /tmp).
constexpr char kRoudiSocket[] = "/tmp/roudi";
// Later configuration entries override earlier ones: this one turns shared memory off.
constexpr char kSharedMemoryOff[] = "<SharedMemory><Enable>false</Enable></SharedMemory>";

std::optional<bool> shared_memory_setting(const std::string& xml) {
  static const std::regex enable(
      R"(<SharedMemory>[\s\S]*?<Enable>\s*(true|false)\s*</Enable>[\s\S]*?</SharedMemory>)",
      std::regex::icase);
  std::optional<bool> setting;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), enable); it != std::sregex_iterator();
       ++it) {
    setting = strcasecmp((*it)[1].str().c_str(), "true") == 0;
  }
  return setting;
}

}  // namespace

bool configuration_enables_shared_memory(
    const std::string& uri,
    const std::function<std::optional<std::string>(const std::string&)>& read_file) {
  bool enabled = false;
  for (const util::CycloneUriEntry& entry : util::cyclone_uri_entries(uri, read_file)) {
    if (!entry.xml) continue;
    if (const auto setting = shared_memory_setting(*entry.xml)) enabled = *setting;
  }
  return enabled;
}

bool roudi_running() {
  const int fd = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return false;
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  std::strncpy(address.sun_path, kRoudiSocket, sizeof address.sun_path - 1);
  // A datagram connect only names the peer: nothing is sent, refused if nobody is bound.
  const bool ok = ::connect(fd, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return ok;
}

SharedMemoryState ensure_shared_memory_usable() {
  static std::once_flag once;
  static SharedMemoryState state = SharedMemoryState::kNotConfigured;
  std::call_once(once, [] {
    const char* uri = std::getenv("CYCLONEDDS_URI");
    if (!uri || !configuration_enables_shared_memory(uri, util::read_text_file)) return;
    if (roudi_running()) {
      state = SharedMemoryState::kOn;
      return;
    }
    state = SharedMemoryState::kOffNoRouDi;
    const std::string fallback = std::string(uri) + "," + kSharedMemoryOff;
    ::setenv("CYCLONEDDS_URI", fallback.c_str(), 1);
    log::warn("Cyclone shared memory is configured but no iceoryx RouDi daemon runs (",
              kRoudiSocket, "): shared memory off, samples go over the loopback network");
  });
  return state;
}

}  // namespace stereoball::dds
