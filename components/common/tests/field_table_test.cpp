#include "common/params/field_table.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/params/field_table_testing.hpp"
#include "common/params/field_table_yaml.hpp"

namespace stereoball::params {
namespace {

// A small Params struct with one field of each kind, a nested section and a cross-field rule.
struct Limits {
  double min_m = 0;
  double max_m = 0;
};

struct TableDemo {
  TableDemo();
  double rate_hz = 0;
  std::int64_t timeout_ns = 0;
  std::uint32_t count = 0;
  bool enabled = false;
  std::string mode;
  std::string path;
  std::vector<int> ks;
  std::array<double, 3> xyz{};
  Limits limits;
};

FieldTable<Limits> limits_fields() {
  return {{number("min_m", at(&Limits::min_m), 0.5, {0.0, 10.0}, "m", "nearest"),
           number("max_m", at(&Limits::max_m), 4.0, {0.0, 10.0}, "m", "farthest")},
          [](const Limits& l) -> Status {
            if (l.max_m > l.min_m) return {};
            return Error{out_of_range("max_m", l.max_m, {l.min_m, 10.0, true}, "m")};
          }};
}

const FieldTable<TableDemo>& demo_fields() {
  static const FieldTable<TableDemo> table = [] {
    FieldTable<TableDemo> t{{
        number("rate_hz", at(&TableDemo::rate_hz), 30.0, {0.0, 1000.0, true}, "Hz",
               "frames | second"),
        number("timeout_ns", at(&TableDemo::timeout_ns), 300'000'000, {1, 3'600'000'000'000}, "ns",
               "stale after"),
        number("count", at(&TableDemo::count), 4u, {0, 32}, "", "buffers"),
        flag("enabled", at(&TableDemo::enabled), true, "on or off"),
        choice("mode", at(&TableDemo::mode), "a", {"a", "b"}, "which mode"),
        optional(text("path", at(&TableDemo::path), "", "a file")),
        list("ks", at(&TableDemo::ks), {5}, {1, 31}, "px", "half windows"),
        list("xyz", at(&TableDemo::xyz), {0.5, 0.0, -0.5}, {-1.0, 1.0}, "m", "offset"),
    }};
    auto limits = section("limits", &TableDemo::limits, limits_fields());
    t.fields.insert(t.fields.end(), limits.fields.begin(), limits.fields.end());
    t.cross_check = limits.cross_check;
    return t;
  }();
  return table;
}

TableDemo::TableDemo() {
  apply_defaults(demo_fields(), *this);
}

const char* kShipped =
    "rate_hz: 30.0\ntimeout_ns: 300000000\ncount: 4\nenabled: true\nmode: a\nks: [5]\n"
    "xyz: [0.5, 0, -0.5]\nlimits:\n  min_m: 0.5\n  max_m: 4\n";

std::string shipped_file() {
  const auto path = std::filesystem::temp_directory_path() / "sb_field_table_demo.yaml";
  std::ofstream(path) << kShipped;
  return path.string();
}

TEST(FieldTable, GivenDemoTableThenItMeetsTheContractEveryComponentTableMeets) {
  testing::expect_table_contract(demo_fields(), shipped_file());
}

TEST(FieldTable, GivenDefaultConstructedStructThenValuesComeFromTheTable) {
  const TableDemo d;
  EXPECT_EQ(d.rate_hz, 30.0);
  EXPECT_EQ(d.timeout_ns, 300'000'000);
  EXPECT_EQ(d.ks, std::vector<int>{5});
  EXPECT_EQ(d.xyz[2], -0.5);
  EXPECT_EQ(d.limits.max_m, 4.0);
  EXPECT_TRUE(check_fields(demo_fields(), d));
}

TEST(FieldTable, GivenOutOfRangeValueThenErrorNamesFileKeyRangeAndUnit) {
  auto p = parse_fields(demo_fields(), std::string(kShipped) + "", "d.yaml");
  ASSERT_TRUE(p.ok()) << p.error();
  std::string text = kShipped;
  text.replace(text.find("rate_hz: 30.0"), 13, "rate_hz: 0");
  p = parse_fields(demo_fields(), text, "d.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(), "d.yaml: key 'rate_hz': 0 is out of range (0, 1000] Hz");

  text = kShipped;
  text.replace(text.find("ks: [5]"), 7, "ks: [5, 2.5]");
  p = parse_fields(demo_fields(), text, "d.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(), "d.yaml: key 'ks': entries must be whole numbers, got 2.5");

  text = kShipped;
  text.replace(text.find("count: 4"), 8, "count: -1");
  p = parse_fields(demo_fields(), text, "d.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(), "d.yaml: key 'count': -1 is out of range [0, 32]");
}

TEST(FieldTable, GivenBadChoiceOrNaNThenRefusedWithTheKey) {
  std::string text = kShipped;
  text.replace(text.find("mode: a"), 7, "mode: c");
  auto p = parse_fields(demo_fields(), text, "d.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(), "d.yaml: key 'mode': 'c' is not one of: a, b");

  TableDemo d;
  d.limits.min_m = std::nan("");
  const auto st = check_fields(demo_fields(), d);
  ASSERT_FALSE(st);
  EXPECT_EQ(st.error(), "key 'limits.min_m': nan is out of range [0, 10] m");
}

TEST(FieldTable, GivenCrossFieldRuleBrokenThenErrorNamesFileAndKey) {
  std::string text = kShipped;
  text.replace(text.find("max_m: 4"), 8, "max_m: 0.2");
  auto p = parse_fields(demo_fields(), text, "d.yaml");
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error(), "d.yaml: key 'max_m': 0.2 is out of range (0.5, 10] m");
}

TEST(FieldTable, GivenOptionalKeyThenReadWhenPresentAndDefaultWhenAbsent) {
  auto absent = parse_fields(demo_fields(), kShipped, "d.yaml");
  ASSERT_TRUE(absent.ok()) << absent.error();
  EXPECT_EQ(absent->path, "");
  auto present = parse_fields(demo_fields(), std::string(kShipped) + "path: /tmp/x\n", "d.yaml");
  ASSERT_TRUE(present.ok()) << present.error();
  EXPECT_EQ(present->path, "/tmp/x");
}

TEST(FieldTable, GivenStructThenYamlReadsBackToTheSameValues) {
  TableDemo d;
  d.rate_hz = 0.1 + 0.2;  // no short decimal: the text must still read back exactly
  d.path = "dir with: colon";
  d.xyz = {1.0 / 3.0, 0.0, -1.0};
  auto back = parse_fields(demo_fields(), to_yaml(demo_fields(), d), "w.yaml");
  ASSERT_TRUE(back.ok()) << back.error() << "\n" << to_yaml(demo_fields(), d);
  EXPECT_EQ(back->rate_hz, d.rate_hz);
  EXPECT_EQ(back->path, d.path);
  EXPECT_EQ(back->xyz, d.xyz);
}

TEST(FieldTable, GivenTableThenMarkdownListsKeyDefaultRangeUnitAndText) {
  const std::string md = markdown_table(specs(demo_fields()));
  EXPECT_NE(md.find("| `rate_hz` | 30.0 | (0, 1000] | Hz | frames \\| second |\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `ks` | [5] | 1 or more whole numbers in [1, 31] | px | half windows |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| `path` | \"\" | text |  | a file (optional) |"), std::string::npos) << md;
  EXPECT_NE(md.find("| `limits.max_m` | 4.0 | [0, 10] | m | farthest |"), std::string::npos) << md;
}

}  // namespace
}  // namespace stereoball::params
