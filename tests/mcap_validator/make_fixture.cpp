// Writes an MCAP file with our writer holding several messages of every topic of the table,
// CDR-encoded (XCDR1, little endian, as Cyclone DDS writes final types) by a small encoder
// written for this test, plus a JSON file with the values each message must decode to.
//   mcap_validator_fixture OUT.mcap OUT_expected.json

#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "recorder/core/writer.hpp"
#include "recorder/io/file_io.hpp"
#include "stereoball/idl_text.hpp"
#include "stereoball/topics.hpp"

using nlohmann::json;
namespace rec = stereoball::recorder;

namespace {

// Arrays longer than this are described by length and byte sum in the expected JSON.
constexpr size_t kSummarizeAbove = 1000;

// Builds one sample's CDR bytes and the JSON of its expected decoded value side by side.
class Sample {
 public:
  Sample() : cdr_{0x00, 0x01, 0x00, 0x00} { stack_.push_back(&root_); }

  template <class T>
  void prim(T v) {
    align(sizeof(T));
    uint8_t raw[sizeof(T)];
    std::memcpy(raw, &v, sizeof(T));  // host is little endian (x86-64/arm64)
    cdr_.insert(cdr_.end(), raw, raw + sizeof(T));
  }
  Sample& u64(const char* n, uint64_t v) {
    prim(v);
    return set(n, std::to_string(v));
  }
  Sample& i64(const char* n, int64_t v) {
    prim(v);
    return set(n, std::to_string(v));
  }
  Sample& u32(const char* n, uint32_t v) {
    prim(v);
    return set(n, v);
  }
  Sample& i32(const char* n, int32_t v) {
    prim(v);
    return set(n, v);
  }
  Sample& enumeration(const char* n, uint32_t v) { return u32(n, v); }
  Sample& f32(const char* n, float v) {
    prim(v);
    return set(n, static_cast<double>(v));
  }
  Sample& f64(const char* n, double v) {
    prim(v);
    return set(n, v);
  }
  Sample& boolean(const char* n, bool v) {
    prim<uint8_t>(v ? 1 : 0);
    return set(n, v);
  }
  Sample& str(const char* n, const std::string& s) {
    prim<uint32_t>(static_cast<uint32_t>(s.size() + 1));
    cdr_.insert(cdr_.end(), s.begin(), s.end());
    cdr_.push_back(0);
    return set(n, s);
  }
  Sample& f64_array(const char* n, const std::vector<double>& v) {
    for (double d : v) prim(d);
    return set(n, v);
  }
  Sample& f64_seq(const char* n, const std::vector<double>& v) {
    prim<uint32_t>(static_cast<uint32_t>(v.size()));
    return f64_array(n, v);
  }
  Sample& octet_array(const char* n, const std::vector<uint8_t>& v) {
    cdr_.insert(cdr_.end(), v.begin(), v.end());
    return set(n, describe(v));
  }
  Sample& octet_seq(const char* n, const std::vector<uint8_t>& v) {
    prim<uint32_t>(static_cast<uint32_t>(v.size()));
    return octet_array(n, v);
  }
  /// Nested struct member n, filled by body.
  Sample& nested(const char* n, const std::function<void(Sample&)>& body) {
    json& child = (*stack_.back())[n] = json::object();
    stack_.push_back(&child);
    body(*this);
    stack_.pop_back();
    return *this;
  }
  /// Sequence of structs n with count elements; body(sample, index) fills each.
  Sample& struct_seq(const char* n, size_t count,
                     const std::function<void(Sample&, size_t)>& body) {
    prim<uint32_t>(static_cast<uint32_t>(count));
    json& arr = (*stack_.back())[n] = json::array();
    for (size_t i = 0; i < count; ++i) {
      arr.push_back(json::object());
      stack_.push_back(&arr.back());
      body(*this, i);
      stack_.pop_back();
    }
    return *this;
  }
  const std::vector<uint8_t>& cdr() const { return cdr_; }
  const json& value() const { return root_; }

 private:
  static json describe(const std::vector<uint8_t>& v) {
    if (v.size() <= kSummarizeAbove) return v;
    uint64_t sum = 0;
    for (uint8_t b : v) sum += b;
    return json{{"$len", v.size()}, {"$sum", sum}};
  }
  template <class V>
  Sample& set(const char* n, V&& v) {
    (*stack_.back())[n] = std::forward<V>(v);
    return *this;
  }
  // XCDR1: primitives align to their size, counted from the end of the encapsulation header.
  void align(size_t n) {
    while ((cdr_.size() - 4) % n != 0) cdr_.push_back(0);
  }
  std::vector<uint8_t> cdr_;
  json root_ = json::object();
  std::vector<json*> stack_;
};

std::vector<uint8_t> pattern(size_t n, int seed) {
  std::vector<uint8_t> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>((i * 31 + seed * 7) & 0xFF);
  return v;
}

std::vector<double> ramp(size_t n, double start) {
  std::vector<double> v(n);
  for (size_t i = 0; i < n; ++i) v[i] = start + 0.25 * static_cast<double>(i);
  return v;
}

// The AuthTag every authenticated topic ends with (idl/stereoball.idl).
void auth(Sample& s, int k) {
  s.nested("auth", [&](Sample& a) {
    a.u32("key_id", 1 + k).u64("link_id", 0x0123456789abcdefull + k).i64("stamp_ns", 77 + k);
    a.octet_array("mac", pattern(32, k + 50));
  });
}

void eye(Sample& s, int k, uint32_t w, uint32_t h) {
  s.i64("capture_stamp_ns", 1'700'000'000'000'000'000 + k)
      .u32("width_px", w)
      .u32("height_px", h)
      .u32("step_bytes", w * 3)
      .octet_seq("data", pattern(size_t{w} * h * 3, k));
}

void stereo_frame(Sample& s, int k) {
  // The last sample is a full 640x480 frame, so a multi-megabyte message is checked too.
  const uint32_t w = k == 2 ? 640 : 8, h = k == 2 ? 480 : 4;
  s.u64("seq", 1000 + k).i64("stamp_ns", 1'700'000'000'000'000'000 + k);
  s.str("source", "simulator").str("encoding", "bgr8").boolean("rectified", k % 2 == 1);
  s.nested("left", [&](Sample& e) { eye(e, k, w, h); });
  s.nested("right", [&](Sample& e) { eye(e, k + 100, w, h); });
}

void calibration(Sample& s, int k) {
  s.i64("stamp_ns", -5 - k).u32("width_px", 640).u32("height_px", 480);
  s.f64_array("k1", ramp(9, 1.0 + k)).f64_seq("d1", ramp(5, -0.5));
  s.f64_array("k2", ramp(9, 2.0)).f64_seq("d2", ramp(static_cast<size_t>(k) * 7, 0.125));
  s.f64_array("r", ramp(9, 0)).f64_array("t", ramp(3, -0.06)).f64_array("r1", ramp(9, 1));
  s.f64_array("r2", ramp(9, 2)).f64_array("p1", ramp(12, 3)).f64_array("p2", ramp(12, 4));
  s.f64_array("q", ramp(16, 5)).f64("rms_px", 0.375).str("source", "calib_" + std::to_string(k));
  auth(s, k);
}

void circle(Sample& s, float base) {
  s.f32("x_px", base).f32("y_px", base + 0.5f).f32("radius_px", 12.25f).f32("score", 0.75f);
}

void detection(Sample& s, int k) {
  s.u64("frame_seq", 7 + k).i64("capture_stamp_ns", 123456789 + k).i64("publish_stamp_ns", 9 + k);
  s.enumeration("status", static_cast<uint32_t>(k)).str("reason", k ? "" : "found");
  s.nested("left", [&](Sample& c) { circle(c, 100.5f + k); });
  s.nested("right", [&](Sample& c) { circle(c, 80.25f); });
  s.f32("row_residual_px", 0.5f).f64_array("position_m", {0.1, -0.2, 1.5 + k});
  s.f32("depth_from_size_m", 1.625f).u32("candidates_left", 3).u32("candidates_right", 1 + k);
  s.f32("processing_ms", 2.5f)
      .boolean("patch_valid", true)
      .octet_array("patch_rgb", pattern(1323, k));
  auth(s, k);
}

void track(Sample& s, int k) {
  s.u64("frame_seq", 70 + k).i64("capture_stamp_ns", 5).i64("publish_stamp_ns", 6);
  s.enumeration("state", static_cast<uint32_t>(k % 3)).enumeration("verdict", 4);
  s.str("reason", "ssd below threshold").boolean("position_valid", k != 1);
  s.f64_array("position_m", {0.5, 0.0, 2.0}).f64_array("velocity_mps", {-0.25, 0, 0.125});
  s.f64("bearing_rad", 0.244978663126864).f64("distance_m", 2.0615528128088303);
  s.enumeration("last_seen_side", 2).f64("ssd", -1.0).i64("last_accepted_stamp_ns", 44 + k);
  auth(s, k);
}

void velocity(Sample& s, int k) {
  s.u64("seq", 300 + k).i64("stamp_ns", 1'700'000'000'123'456'789 + k);
  s.i64("capture_stamp_ns", 1'700'000'000'100'000'000 + k);
  s.f64("linear_mps", 0.5 * k).f64("angular_radps", -0.125).str("source", "motion_controller");
  auth(s, k);
}

void estop(Sample& s, int k) {
  s.i64("stamp_ns", 99 + k).boolean("engaged", k == 1).str("reason", k == 1 ? "button" : "");
  auth(s, k);
}

void ground_truth(Sample& s, int k) {
  s.u64("frame_seq", 1000 + k).i64("stamp_ns", 1'700'000'000'000'000'000 + k);
  s.f64("sim_time_s", 0.016 * k).str("scenario", "rolling_ball").boolean("ball_present", true);
  s.f64("ball_radius_m", 0.11).f64_array("ball_world_m", {1, 2, 0.11});
  s.f64_array("ball_camera_m", {0.2, 0.1, 2.5}).boolean("ball_visible_left", true);
  s.boolean("ball_visible_right", k != 2).f64_array("ball_left_px", {320.5, 240.25});
  s.f64_array("ball_right_px", {300.5, 240.25}).f64("robot_x_m", 0.1 * k).f64("robot_y_m", -1);
  s.f64("robot_yaw_rad", 0.7853981633974483).f64("robot_linear_mps", 0.3);
  s.f64("robot_angular_radps", 0.05);
}

void status(Sample& s, int k) {
  s.str("component", "tracker").str("host", "robot-1").i32("pid", 4242 + k).i64("stamp_ns", 17);
  s.f64("uptime_s", 12.5 * k).boolean("healthy", k != 1).str("state", "following");
  s.struct_seq("rates", static_cast<size_t>(k), [&](Sample& r, size_t i) {
    r.str("topic", "ball/detection").f32("rate_hz", 59.75f).u64("count", 100 + i).u64("dropped", i);
  });
  s.struct_seq("counters", 2, [&](Sample& c, size_t i) {
    c.str("name", i ? "rejected" : "accepted").u64("value", 18446744073709551615ull - i);
  });
  s.u64("errors", 3).str("last_error", k ? "timeout" : "");
}

const std::map<std::string, std::function<void(Sample&, int)>>& generators() {
  static const std::map<std::string, std::function<void(Sample&, int)>> kGen = {
      {"stereoball::msg::StereoFrame", stereo_frame},
      {"stereoball::msg::StereoCalibration", calibration},
      {"stereoball::msg::BallDetection", detection},
      {"stereoball::msg::BallTrack", track},
      {"stereoball::msg::VelocityCommand", velocity},
      {"stereoball::msg::EmergencyStop", estop},
      {"stereoball::msg::GroundTruth", ground_truth},
      {"stereoball::msg::ComponentStatus", status}};
  return kGen;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: mcap_validator_fixture OUT.mcap OUT_expected.json\n");
    return 2;
  }
  auto sink = rec::FileSink::create(argv[1]);
  if (!sink) return std::fprintf(stderr, "fixture: %s\n", sink.error().c_str()), 1;
  rec::WriterParams params;
  params.chunk_size_bytes = 64 * 1024;  // several chunks
  rec::McapWriter writer(params);
  if (auto e = writer.open(**sink); !e)
    return std::fprintf(stderr, "fixture: %s\n", e.error().c_str()), 1;

  json expected = json::array();
  uint64_t t = 1'700'000'000'000'000'000ull;
  uint32_t sequence = 0;
  for (const auto& spec : stereoball::topics::all()) {
    const std::string type(spec.type_name);
    const auto gen = generators().find(type);
    if (gen == generators().end()) {
      std::fprintf(stderr, "fixture: no generator for type %s (update make_fixture.cpp)\n",
                   type.c_str());
      return 1;
    }
    const auto schema = writer.add_schema(type, "omgidl", stereoball::idl_text());
    const auto channel = writer.add_channel(schema.value(), spec.name, "cdr");
    if (!channel) return std::fprintf(stderr, "fixture: %s\n", channel.error().c_str()), 1;
    for (int k = 0; k < 3; ++k) {
      Sample s;
      gen->second(s, k);
      t += 1'000'000;
      const uint64_t publish = t - 250'000;
      if (auto e = writer.write({channel.value(), sequence, t, publish, s.cdr()}); !e) {
        return std::fprintf(stderr, "fixture: %s\n", e.error().c_str()), 1;
      }
      expected.push_back({{"topic", spec.name},
                          {"schema", type},
                          {"sequence", sequence++},
                          {"log_time", std::to_string(t)},
                          {"publish_time", std::to_string(publish)},
                          {"value", s.value()}});
    }
  }
  if (auto e = writer.close(); !e)
    return std::fprintf(stderr, "fixture: %s\n", e.error().c_str()), 1;
  std::ofstream(argv[2]) << expected.dump(1) << "\n";
  std::printf("fixture: %zu messages, %llu chunks -> %s\n", expected.size(),
              static_cast<unsigned long long>(writer.stats().chunks), argv[1]);
  return 0;
}
