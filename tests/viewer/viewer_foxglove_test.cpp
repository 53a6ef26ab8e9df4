// Foxglove, live and recorded: Foxglove's own npm client reads `stereoball view`'s WebSocket
// server, and the MCAP validator (Foxglove's MCAP and CDR packages) reads the derived
// channels `stereoball record` writes. Both compare what they decode with what was published.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "viewer_test_support.hpp"

namespace stereoball::testing {
namespace {

using namespace std::chrono_literals;

nlohmann::json expected_json(const SceneValues& v) {
  return {{"timeout_ms", 40000},
          {"channels",
           {{"view/left/image", "foxglove::CompressedImage"},
            {"view/right/image", "foxglove::CompressedImage"},
            {"view/left/annotations", "foxglove::ImageAnnotations"},
            {"view/right/annotations", "foxglove::ImageAnnotations"},
            {"view/scene", "foxglove::SceneUpdate"},
            {"view/transforms", "foxglove::FrameTransforms"},
            {"view/plot", "stereoball.view.Plot"}}},
          {"image",
           {{"width", v.width_px},
            {"height", v.height_px},
            {"sec", v.capture_stamp_ns / 1'000'000'000},
            {"nsec", v.capture_stamp_ns % 1'000'000'000}}},
          {"left_circle", {{"x", v.left_x}, {"y", v.left_y}, {"radius", v.left_r}}},
          {"right_circle", {{"x", v.right_x}, {"y", v.left_y}, {"radius", v.right_r}}},
          {"track_position", v.track_position},
          {"truth_ball_world", v.truth_ball_world},
          {"robot_xy", v.robot_xy},
          {"track_state", "following"},
          {"distance_m", v.distance_m}};
}

class ViewerFoxglove : public ::testing::Test {
 protected:
  void SetUp() override {
    if (node_binary().empty() || npm_dir().empty())
      GTEST_SKIP() << "node or the tests' npm packages are missing (SB_VIEWER_NPM_DIR)";
  }
};

TEST_F(ViewerFoxglove, FoxgloveClientDecodesEveryChannelAsPublished) {
  // Given the viewer and a publisher of a known scene
  const std::string partition = unique_partition();
  auto viewer = start_viewer(partition);
  ASSERT_GT(viewer.port, 0) << viewer.process.output();
  KnownScene scene(partition, 20);
  const std::string expected = temp_dir() + "/expected.json";
  std::ofstream(expected) << expected_json(scene.values()).dump();
  // When Foxglove's client connects, subscribes to everything and sends bad requests
  const auto [rc, out] = run({node_binary(), npm_dir() + "/foxglove_client.mjs",
                              "ws://127.0.0.1:" + std::to_string(viewer.port) + "/", expected},
                             90s);
  // Then it found every published value in the decoded channels, got a status for each bad
  // request, and kept receiving messages
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("OK "), std::string::npos) << out;
  EXPECT_GE(stats_counter(viewer.port, "bad_client_messages"), 3) << out;
  std::printf("%s", out.c_str());
}

TEST_F(ViewerFoxglove, RecorderDerivedChannelsDecodeWithFoxgloveSchemasAndPlayIgnoresThem) {
  // Given a publisher of a known scene and a recording with the derived channels (--all)
  const std::string partition = unique_partition();
  KnownScene scene(partition, 20);
  const std::string file = temp_dir() + "/derived.mcap";
  const auto [rc, out] = run({bin("stereoball-record"), "--all", "-q", "--duration", "4",
                              "--partition", partition, "-o", file},
                             60s);
  ASSERT_EQ(rc, 0) << out;
  // When the independent validator reads it
  const auto [vrc, vout] = run({node_binary(), npm_dir() + "/validate.mjs", file}, 120s);
  // Then every message of every channel decodes with its stored schema, derived ones included
  EXPECT_EQ(vrc, 0) << vout;
  for (const char* topic : {"view/left/image", "view/right/image", "view/left/annotations",
                            "view/scene", "view/transforms"})
    EXPECT_NE(vout.find(topic), std::string::npos) << topic << " missing: " << vout;
  // And the derived decoded values are the published ones (spot check via the derived JSON)
  const auto [drc, dout] = run({node_binary(), npm_dir() + "/derived_dump.mjs", file}, 60s);
  ASSERT_EQ(drc, 0) << dout;
  const auto dump = nlohmann::json::parse(dout);
  const auto& v = scene.values();
  EXPECT_EQ(dump["view/left/image"]["format"], "jpeg");
  EXPECT_EQ(dump["view/left/image"]["width"], v.width_px);
  EXPECT_NEAR(dump["view/left/annotations"]["circle_x"].get<double>(), v.left_x, 1e-3);
  EXPECT_NEAR(dump["view/scene"]["ball_z"].get<double>(), v.track_position[2], 1e-9);

  // And play republishes the table's topics but not the derived channels
  const auto [prc, pout] = run({bin("stereoball-play"), file, "--rate", "20", "--wait", "0",
                                "--partition", partition + ".play"},
                               60s);
  EXPECT_EQ(prc, 0) << pout;
  EXPECT_NE(pout.find("ignoring view/left/image (derived foxglove::CompressedImage"),
            std::string::npos)
      << pout;
  EXPECT_EQ(pout.find("playing view/"), std::string::npos) << pout;
  EXPECT_NE(pout.find("playing ball/track"), std::string::npos) << pout;
}

}  // namespace
}  // namespace stereoball::testing
