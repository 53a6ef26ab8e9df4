// Cyclone shared memory only when it can work: configuration parsing, and a participant that
// starts (shared memory off, one warning) when the configuration asks for it but no iceoryx
// RouDi daemon runs, instead of Cyclone waiting for RouDi forever.

#include "common/dds/shared_memory.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>

#include "common/dds/participant.hpp"

namespace stereoball::dds {
namespace {

const std::map<std::string, std::string> kFiles{
    {"/cfg/shm.xml",
     "<CycloneDDS><Domain><SharedMemory>\n  <Enable>true</Enable>\n  <LogLevel>warn</LogLevel>\n"
     "</SharedMemory></Domain></CycloneDDS>"},
    {"/cfg/plain.xml", "<CycloneDDS><Domain><General/></Domain></CycloneDDS>"}};

std::optional<std::string> fake_read(const std::string& path) {
  const auto it = kFiles.find(path);
  if (it == kFiles.end()) return std::nullopt;
  return it->second;
}

TEST(SharedMemoryConfiguration, GivenUriLists_ThenTheLastSettingWins) {
  EXPECT_TRUE(configuration_enables_shared_memory("file:///cfg/shm.xml", fake_read));
  EXPECT_FALSE(configuration_enables_shared_memory("file:///cfg/plain.xml", fake_read));
  EXPECT_FALSE(configuration_enables_shared_memory("file:///missing.xml", fake_read));
  // An inline override after the file turns it off, and on again
  EXPECT_FALSE(configuration_enables_shared_memory(
      "file:///cfg/shm.xml,<SharedMemory><Enable>false</Enable></SharedMemory>", fake_read));
  EXPECT_TRUE(configuration_enables_shared_memory(
      "file:///cfg/plain.xml, <SharedMemory><Enable>TRUE</Enable></SharedMemory>", fake_read));
}

TEST(SharedMemoryFallback, GivenSharedMemoryConfiguredButNoRouDi_ThenParticipantStartsWithoutIt) {
  if (roudi_running()) GTEST_SKIP() << "an iceoryx RouDi runs on this host";
  // Given the test's Cyclone configuration plus shared memory on
  const char* base = std::getenv("CYCLONEDDS_URI");
  const std::string uri = std::string(base ? base : "") + (base ? "," : "") +
                          "<SharedMemory><Enable>true</Enable></SharedMemory>";
  ::setenv("CYCLONEDDS_URI", uri.c_str(), 1);
  // When a participant is created (ctest's timeout catches a wait for RouDi)
  DomainParticipant participant({domain_from_env(0), "shm-fallback"});
  // Then shared memory was switched off for this process, by an override at the end
  EXPECT_EQ(ensure_shared_memory_usable(), SharedMemoryState::kOffNoRouDi);
  const std::string now = std::getenv("CYCLONEDDS_URI");
  EXPECT_NE(now.find(uri + ",<SharedMemory><Enable>false</Enable>"), std::string::npos) << now;
  EXPECT_GT(participant.handle(), 0);
}

}  // namespace
}  // namespace stereoball::dds
