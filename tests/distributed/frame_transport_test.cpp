// Frames published in the robot namespace reach an observer in the workstation namespace.
#include "frame_transport.hpp"

#include <gtest/gtest.h>

#include "process.hpp"

namespace sd = stereoball::distributed;

TEST(FrameTransportAcrossTheLink, RawAndJpegFramesReachTheWorkstation) {
  // Given two namespaces joined by veth (root and iproute2)
  sd::TwoHosts hosts;
  if (auto e = hosts.setup(); !e) GTEST_SKIP() << "no two namespaces here: " << e.error();
  for (const std::string encoding : {"bgr8", "jpeg"}) {
    // When the frame publisher runs for two seconds in the robot namespace
    sd::FrameTransportOptions options;
    options.encoding = encoding;
    options.duration_s = 2;
    options.rate_hz = 10;
    options.domain = stereoball::testing::test_domain();
    options.partition = stereoball::testing::unique_partition() + "." + encoding;
    const auto run = sd::run_frame_transport(hosts, options);
    // Then the observer across the link receives its frames, whole and in that encoding
    ASSERT_TRUE(run) << run.error();
    EXPECT_GT(run->sent, 0);
    ASSERT_FALSE(run->received.empty()) << encoding << ": none of " << run->sent << " arrived";
    EXPECT_LE(static_cast<long>(run->received.size()), run->sent);
    for (const auto& f : run->received) {
      EXPECT_EQ(f.encoding, encoding);
      EXPECT_GT(f.bytes, 0u);
    }
  }
}
