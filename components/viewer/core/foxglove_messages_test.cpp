#include "viewer/core/foxglove_messages.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "viewer/core/cdr_writer.hpp"

namespace stereoball::viewer::foxglove {
namespace {

// Reads back plain little-endian CDR the way a CDR decoder does (alignment from the payload
// start), so the tests check the layout, not just the byte count.
class CdrReader {
 public:
  explicit CdrReader(const std::vector<uint8_t>& b) : b_(b) {}
  template <typename T>
  T get() {
    while ((at_ - 4) % sizeof(T)) ++at_;
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string string() {
    const auto n = get<uint32_t>();
    std::string s(reinterpret_cast<const char*>(b_.data() + at_), n - 1);
    at_ += n;
    return s;
  }
  size_t at() const { return at_; }
  void skip(size_t n) { at_ += n; }

 private:
  const std::vector<uint8_t>& b_;
  size_t at_ = 4;
};

TEST(CdrWriter, AlignsEachPrimitiveToItsSizeAfterTheHeader) {
  CdrWriter w;
  w.u8(1);
  w.f64(2.5);
  w.boolean(true);
  w.u32(7);
  const auto& b = w.bytes();
  ASSERT_EQ(b.size(), 4u + 1 + 7 + 8 + 1 + 3 + 4);
  EXPECT_EQ(b[1], 0x01);  // CDR_LE
  double d;
  std::memcpy(&d, b.data() + 12, 8);
  EXPECT_EQ(d, 2.5);
  EXPECT_EQ(b[24], 7);
}

TEST(FoxgloveMessages, CompressedImageCarriesStampFrameBytesAndFormat) {
  const std::vector<uint8_t> jpeg = {0xFF, 0xD8, 0x01, 0x02, 0xFF, 0xD9};
  const auto cdr = compressed_image(3'000'000'005, Eye::kRight, jpeg);
  CdrReader r(cdr);
  EXPECT_EQ(r.get<uint32_t>(), 3u);
  EXPECT_EQ(r.get<uint32_t>(), 5u);
  EXPECT_EQ(r.string(), "camera_right");
  ASSERT_EQ(r.get<uint32_t>(), jpeg.size());
  EXPECT_EQ(std::vector<uint8_t>(cdr.begin() + r.at(), cdr.begin() + r.at() + 6), jpeg);
  r.skip(6);
  EXPECT_EQ(r.string(), "jpeg");
  EXPECT_EQ(r.at(), cdr.size());
}

TEST(FoxgloveMessages, AnnotationsDrawTheCircleOrSayWhyThereIsNone) {
  Detection found;
  found.found = true;
  found.left = {100, 50, 20, 0.8};
  const auto circle_cdr = image_annotations(found, Eye::kLeft, 640);
  CdrReader with_circle(circle_cdr);
  with_circle.get<uint32_t>();
  with_circle.get<uint32_t>();
  EXPECT_EQ(with_circle.get<uint32_t>(), 1u);  // one circle
  with_circle.get<uint32_t>();
  with_circle.get<uint32_t>();
  EXPECT_EQ(with_circle.get<double>(), 100.0);
  EXPECT_EQ(with_circle.get<double>(), 50.0);
  EXPECT_EQ(with_circle.get<double>(), 40.0);  // diameter

  // An eye shown at half its width gets the circle at half its coordinates and size
  const auto half_cdr = image_annotations(found, Eye::kLeft, 320, 0.5);
  CdrReader half(half_cdr);
  for (int i = 0; i < 5; ++i) half.get<uint32_t>();
  EXPECT_EQ(half.get<double>(), 50.0);
  EXPECT_EQ(half.get<double>(), 25.0);
  EXPECT_EQ(half.get<double>(), 20.0);  // diameter

  Detection refused;
  refused.status = "epipolar_mismatch";
  refused.reason = "rows differ by 9 px";
  const auto cdr = image_annotations(refused, Eye::kLeft, 640);
  CdrReader r(cdr);
  r.get<uint32_t>();
  r.get<uint32_t>();
  EXPECT_EQ(r.get<uint32_t>(), 0u);  // no circle
  EXPECT_EQ(r.get<uint32_t>(), 0u);  // no points
  EXPECT_EQ(r.get<uint32_t>(), 1u);  // one text
  r.get<uint32_t>();
  r.get<uint32_t>();
  r.get<double>();
  r.get<double>();
  EXPECT_EQ(r.string(), "epipolar_mismatch: rows differ by 9 px");
}

TEST(FoxgloveMessages, SceneHoldsRobotBallRegisterSearchAndTruthEntities) {
  Scene scene({});
  Track t;
  t.state = "following";
  t.accepted = t.position_valid = true;
  t.position_m = {0.2, 0.1, 1.5};
  scene.apply(t);
  const auto cdr = scene_update(scene, 1'000'000'000);
  CdrReader r(cdr);
  EXPECT_EQ(r.get<uint32_t>(), 0u);  // deletions
  EXPECT_EQ(r.get<uint32_t>(), 5u);  // robot, ball_estimate, register, search, truth
  r.get<uint32_t>();
  r.get<uint32_t>();
  EXPECT_EQ(r.string(), "robot");
  EXPECT_EQ(r.string(), "robot");
  EXPECT_NE(std::string(schema_idl()).find("struct SceneUpdate"), std::string::npos);
}

TEST(FoxgloveMessages, PlotJsonHasTheLatestTrackAndCommand) {
  Scene scene({});
  Track t;
  t.state = "searching";
  t.distance_m = 1.25;
  scene.apply(t);
  scene.apply(Command{1, 0.3, -0.2});
  const auto j = nlohmann::json::parse(plot_json(scene));
  EXPECT_EQ(j["track_state"], "searching");
  EXPECT_EQ(j["track_state_code"], 2);
  EXPECT_EQ(j["distance_m"], 1.25);
  EXPECT_EQ(j["angular_radps"], -0.2);
}

}  // namespace
}  // namespace stereoball::viewer::foxglove
