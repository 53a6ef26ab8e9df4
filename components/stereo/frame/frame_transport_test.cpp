#include "stereo/frame/frame_transport.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <map>

namespace stereoball::stereo {
namespace {

TEST(ParseCycloneSize, GivenCycloneSizeTextsWhenParsedThenBinaryUnitsOrNothing) {
  EXPECT_EQ(parse_cyclone_size("16MB"), 16u << 20);
  EXPECT_EQ(parse_cyclone_size("1MiB"), 1u << 20);
  EXPECT_EQ(parse_cyclone_size("64kB"), 64u << 10);
  EXPECT_EQ(parse_cyclone_size("65500B"), 65500u);
  EXPECT_EQ(parse_cyclone_size("4194304"), 4194304u);
  EXPECT_EQ(parse_cyclone_size("2 GB"), 2ull << 30);
  EXPECT_EQ(parse_cyclone_size("default"), std::nullopt);
  EXPECT_EQ(parse_cyclone_size("${SIZE}"), std::nullopt);
  EXPECT_EQ(parse_cyclone_size("12 parsecs"), std::nullopt);
  EXPECT_EQ(parse_cyclone_size(""), std::nullopt);
}

TEST(ConfiguredReceiveBuffer, GivenTheProjectsConfigurationsWhenReadThenTheirMaxRequest) {
  // Given the shipped loopback configuration, a min-only one and an inline override
  const std::map<std::string, std::string> files = {
      {"/cfg/loopback.xml",
       R"(<CycloneDDS><Domain><Internal>
            <SocketReceiveBufferSize min="default" max="16MB"/>
          </Internal></Domain></CycloneDDS>)"},
      {"/cfg/min.xml", R"(<Internal><SocketReceiveBufferSize min="2MB"/></Internal>)"},
      {"/cfg/none.xml", "<CycloneDDS/>"}};
  auto read = [&](const std::string& path) -> std::optional<std::string> {
    const auto it = files.find(path);
    if (it == files.end()) return std::nullopt;
    return it->second;
  };
  // When the request is read, Then max wins over min, later entries override earlier ones
  const auto loopback = configured_receive_buffer("file:///cfg/loopback.xml", read);
  ASSERT_TRUE(loopback.has_value());
  EXPECT_EQ(loopback->first, 16u << 20);
  EXPECT_EQ(loopback->second, "/cfg/loopback.xml");
  EXPECT_EQ(configured_receive_buffer("/cfg/min.xml", read)->first, 2u << 20);
  EXPECT_EQ(configured_receive_buffer(
                "file:///cfg/loopback.xml,<SocketReceiveBufferSize max=\"32MB\"/>", read)
                ->first,
            32u << 20);
  EXPECT_EQ(configured_receive_buffer("file:///cfg/none.xml", read), std::nullopt);
  EXPECT_EQ(configured_receive_buffer("file:///missing.xml", read), std::nullopt);
}

TEST(OversizeWarning, GivenRawFramesLargerThanTwiceTheGrantedBufferThenOneLineNamesEveryRemedy) {
  // Given the shipped loopback request (16 MiB) capped by this kind of kernel at 4 MiB
  TransportLimits limits;
  limits.requested_bytes = 16u << 20;
  limits.requested_from = "SocketReceiveBufferSize in loopback.xml";
  limits.rmem_max_bytes = 4194304;
  EXPECT_EQ(limits.receive_buffer_bytes(), 4194304u);
  EXPECT_EQ(limits.capacity_bytes(), 8388608u);
  // When raw 2304x1296 bgr8 frames (17.9 MB) are checked
  const uint64_t raw = frame_sample_bytes(2304u * 1296 * 3, 2304u * 1296 * 3);
  const auto warning = oversize_warning(raw, limits, "raw 2304x1296 bgr8 frames");
  // Then one line names the sizes and the remedies
  ASSERT_TRUE(warning.has_value());
  EXPECT_EQ(warning->find('\n'), std::string::npos);
  for (const char* part :
       {"raw 2304x1296 bgr8 frames", "17.1 MiB", "about 8.0 MiB", "4.0 MiB receive buffer",
        "asks 16.0 MiB", "rmem_max = 4194304", "frame_encoding: jpeg", "publish_width_px",
        "shm.xml", "90-stereoball-net.conf", "at least 17916928"}) {
    EXPECT_NE(warning->find(part), std::string::npos) << part << " in: " << *warning;
  }
  // And 1152x648 bgr8 frames (4.5 MB, all arrived in the measurement) fit; 1600x900 (8.6 MB,
  // 17 of 40 arrived) do not
  EXPECT_EQ(oversize_warning(frame_sample_bytes(1152u * 648 * 3, 1152u * 648 * 3), limits, "x"),
            std::nullopt);
  EXPECT_NE(oversize_warning(frame_sample_bytes(1600u * 900 * 3, 1600u * 900 * 3), limits, "x"),
            std::nullopt);
  // And nothing is reported over shared memory
  limits.shared_memory = true;
  EXPECT_EQ(oversize_warning(raw, limits, "x"), std::nullopt);
}

TEST(TransportLimits, GivenAnUnknownKernelCapThenTheRequestIsTheBuffer) {
  TransportLimits limits;
  EXPECT_EQ(limits.receive_buffer_bytes(), kCycloneDefaultReceiveBufferBytes);
  limits.rmem_max_bytes = 212992;
  EXPECT_EQ(limits.receive_buffer_bytes(), 212992u);
}

TEST(ReadTransportLimits, GivenAKeylessProcessThenItsBuiltInConfigurationCountsNotTheVariable) {
  // Given CYCLONEDDS_URI asking a 1 MiB buffer, and a built-in configuration asking 16 MiB that
  // replaces it (a process without a deployment key)
  const char* before = std::getenv("CYCLONEDDS_URI");
  const std::string saved = before ? before : "";
  ::setenv("CYCLONEDDS_URI",
           R"(<CycloneDDS><Domain><Internal><SocketReceiveBufferSize max="1MB"/>)"
           R"(</Internal></Domain></CycloneDDS>)",
           1);
  const std::string built_in =
      R"(<CycloneDDS><Domain><Internal><SocketReceiveBufferSize min="default" max="16MB"/>)"
      R"(</Internal></Domain></CycloneDDS>)";
  // When the limits are read with and without the built-in configuration
  const TransportLimits keyless = read_transport_limits({true, built_in});
  const TransportLimits keyed = read_transport_limits({false, ""});
  if (before) {
    ::setenv("CYCLONEDDS_URI", saved.c_str(), 1);
  } else {
    ::unsetenv("CYCLONEDDS_URI");
  }
  // Then the keyless process asks what its built-in configuration asks, has no shared memory
  // (the built-in configuration enables none) and says where the request comes from
  EXPECT_EQ(keyless.requested_bytes, 16u << 20);
  EXPECT_TRUE(keyless.keyless);
  EXPECT_FALSE(keyless.shared_memory);
  EXPECT_NE(keyless.requested_from.find("built-in"), std::string::npos) << keyless.requested_from;
  // And a keyed process follows the variable
  EXPECT_EQ(keyed.requested_bytes, 1u << 20);
  EXPECT_FALSE(keyed.keyless);
}

TEST(TransportRemedies, GivenAKeylessProcessThenNoRemedyNeedsTheVariableItIgnores) {
  const std::string keyless = transport_remedies(17916928, true);
  EXPECT_EQ(keyless.find("shm.xml"), std::string::npos) << keyless;
  for (const char* part : {"frame_encoding: jpeg", "publish_width_px", "at least 17916928",
                           "deployment key", "stereoball keys init"}) {
    EXPECT_NE(keyless.find(part), std::string::npos) << part << " in: " << keyless;
  }
  EXPECT_NE(transport_remedies(17916928, false).find("shm.xml"), std::string::npos);
}

}  // namespace
}  // namespace stereoball::stereo
