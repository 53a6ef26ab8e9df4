#include "viewer/core/scene.hpp"

#include <gtest/gtest.h>

namespace stereoball::viewer {
namespace {

Track accepted_at(double x, double z, uint64_t seq) {
  Track t;
  t.frame_seq = seq;
  t.state = "following";
  t.accepted = true;
  t.position_valid = true;
  t.position_m = {x, 0.1, z};
  t.velocity_mps = {0.5, 0, -1.0};
  return t;
}

TEST(Scene, RegisterKeepsTheLastFiveAcceptedPositions) {
  Scene scene({});
  for (int i = 0; i < 7; ++i) scene.apply(accepted_at(i, 2.0, i));
  Track rejected = accepted_at(100, 100, 8);
  rejected.accepted = false;
  scene.apply(rejected);
  ASSERT_EQ(scene.register_positions().size(), 5u);
  EXPECT_EQ(scene.register_positions().front()[0], 2);
  EXPECT_EQ(scene.register_positions().back()[0], 6);
}

TEST(Scene, EstimateHasTheRegisterSpreadAndPredictionsAlongTheVelocity) {
  Scene scene({});
  for (double x : {1.0, 2.0, 3.0}) scene.apply(accepted_at(x, 2.0, 1));
  const auto e = scene.estimate();
  ASSERT_TRUE(e);
  EXPECT_DOUBLE_EQ(e->sigma_m[0], 1.0);  // sample std of 1, 2, 3
  EXPECT_DOUBLE_EQ(e->sigma_m[2], 0.0);
  ASSERT_EQ(e->predictions_m.size(), 3u);
  EXPECT_DOUBLE_EQ(e->predictions_m[1][0], 3.0 + 0.5 * 1.0);
  EXPECT_DOUBLE_EQ(e->predictions_m[1][2], 2.0 - 1.0 * 1.0);
}

TEST(Scene, ReturnToIdleEmptiesTheRegister) {
  Scene scene({});
  scene.apply(accepted_at(1, 2, 1));
  Track idle;
  idle.state = "idle";
  scene.apply(idle);
  EXPECT_TRUE(scene.register_positions().empty());
  EXPECT_FALSE(scene.estimate());
}

TEST(Scene, JsonCarriesTrackSearchSideCommandsWindowAndStaleNodes) {
  SceneParams p;
  p.command_window_ns = 10;
  Scene scene(p);
  Track searching = accepted_at(1, 2, 3);
  searching.state = "searching";
  searching.last_seen_side = "right";
  scene.apply(searching);
  for (int64_t t : {0, 5, 20}) scene.apply(Command{t, 0.1 * t, 0});
  Health h;
  h.component = "tracker";
  h.stamp_ns = 0;
  scene.apply(h);
  const auto j = scene.to_json(p.health_stale_ns + 1);
  EXPECT_EQ(j["track"]["state"], "searching");
  EXPECT_EQ(j["search_side"], "right");
  ASSERT_EQ(j["commands"].size(), 1u);  // 0 and 5 are older than 20 - 10
  EXPECT_EQ(j["commands"][0][0], 20);
  ASSERT_EQ(j["nodes"].size(), 1u);
  EXPECT_EQ(j["nodes"][0]["stale"], true);
}

TEST(Scene, CommandHistoryIsThinnedForThePageButKeepsTheNewest) {
  SceneParams p;
  p.max_plotted_commands = 10;
  Scene scene(p);
  for (int64_t i = 0; i < 95; ++i) scene.apply(Command{i, static_cast<double>(i), 0});
  const auto commands = scene.to_json(0)["commands"];
  EXPECT_LE(commands.size(), 10u);
  EXPECT_GE(commands.size(), 8u);
  EXPECT_EQ(commands.back()[0], 94);
}

TEST(Scene, DetectionsAreKeptForMatchingToImagesUpToTheLimit) {
  SceneParams p;
  p.recent_detections = 3;
  Scene scene(p);
  for (uint64_t s = 0; s < 5; ++s) {
    Detection d;
    d.frame_seq = s;
    scene.apply(d);
  }
  EXPECT_FALSE(scene.detection_for(1));
  ASSERT_TRUE(scene.detection_for(3));
  EXPECT_EQ(scene.to_json(0)["detections"].size(), 3u);
}

}  // namespace
}  // namespace stereoball::viewer
