#include "common/params/params_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/params/yaml_load.hpp"

namespace stereoball::params {
namespace {

struct Demo {
  double gain = 1.0;
  int count = 5;
  bool enabled = false;
  std::string mode = "a";
  std::vector<double> xyz{0, 0, 0};
};

Status load_demo(const std::string& text, Demo& demo) {
  auto file = ParamsFile::parse(text, "demo.yaml");
  if (!file) return Error{file.error()};
  file->read("gain", demo.gain, 0.0, 10.0);
  file->read("nested.count", demo.count, 1, 100);
  file->read("enabled", demo.enabled);
  file->read_choice("mode", demo.mode, {"a", "b"});
  file->read("xyz", demo.xyz, 3);
  if (auto st = file->finish(); !st) return Error{st.error()};
  return {};
}

const char* kGood = "gain: 2.5\nnested:\n  count: 7\nenabled: true\nmode: b\nxyz: [1, 2, 3]\n";

TEST(ParamsFile, GivenCompleteFileWhenLoadedThenEveryValueIsRead) {
  Demo demo;
  EXPECT_TRUE(load_demo(kGood, demo).ok());
  EXPECT_DOUBLE_EQ(demo.gain, 2.5);
  EXPECT_EQ(demo.count, 7);
  EXPECT_TRUE(demo.enabled);
  EXPECT_EQ(demo.mode, "b");
  EXPECT_EQ(demo.xyz, (std::vector<double>{1, 2, 3}));
}

TEST(ParamsFile, GivenMissingKeyThenErrorNamesFileAndKey) {
  Demo demo;
  auto err = load_demo("gain: 2.5\nenabled: true\nmode: b\nxyz: [1,2,3]\n", demo);
  ASSERT_FALSE(err.ok());
  EXPECT_EQ(err.error(), "demo.yaml: key 'nested.count': missing");
}

TEST(ParamsFile, GivenWrongTypeThenErrorNamesKeyAndValue) {
  Demo demo;
  std::string text = kGood;
  text.replace(text.find("2.5"), 3, "fast");
  auto err = load_demo(text, demo);
  ASSERT_FALSE(err.ok());
  EXPECT_EQ(err.error(), "demo.yaml: key 'gain': expected a number, got 'fast'");
  EXPECT_DOUBLE_EQ(demo.gain, 1.0) << "a bad value must not overwrite the default";
}

TEST(ParamsFile, GivenOutOfRangeThenErrorStatesAllowedRange) {
  Demo demo;
  std::string text = kGood;
  text.replace(text.find("count: 7"), 8, "count: 700");
  auto err = load_demo(text, demo);
  ASSERT_FALSE(err.ok());
  EXPECT_EQ(err.error(), "demo.yaml: key 'nested.count': 700 is out of range [1, 100]");
}

TEST(ParamsFile, GivenUnknownKeyThenItIsReportedAsTypo) {
  Demo demo;
  auto err = load_demo(std::string(kGood) + "gian: 3\n", demo);
  ASSERT_FALSE(err.ok());
  EXPECT_EQ(err.error(), "demo.yaml: key 'gian': unknown parameter");
}

TEST(ParamsFile, GivenBadChoiceOrListThenErrorsAreSpecific) {
  Demo demo;
  std::string text = kGood;
  text.replace(text.find("mode: b"), 7, "mode: z");
  EXPECT_EQ(load_demo(text, demo).error(), "demo.yaml: key 'mode': 'z' is not one of: a, b");
  text = kGood;
  text.replace(text.find("[1, 2, 3]"), 9, "[1, 2]");
  EXPECT_EQ(load_demo(text, demo).error(), "demo.yaml: key 'xyz': expected 3 numbers, got 2");
}

TEST(ParamsFile, GivenIntegerWithFractionThenRejected) {
  Demo demo;
  std::string text = kGood;
  text.replace(text.find("count: 7"), 8, "count: 7.5");
  EXPECT_EQ(load_demo(text, demo).error(),
            "demo.yaml: key 'nested.count': expected an integer, got '7.5'");
}

TEST(ParamsFile, GivenUnreadableOrInvalidFileThenLoadFails) {
  auto missing = ParamsFile::load("/nonexistent/params.yaml");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error(), "/nonexistent/params.yaml: cannot read file");
  auto bad = ParamsFile::parse("gain: [1, 2\n", "bad.yaml");
  ASSERT_FALSE(bad);
  EXPECT_NE(bad.error().find("bad.yaml: not valid YAML"), std::string::npos);
  auto scalar = ParamsFile::parse("42", "scalar.yaml");
  ASSERT_FALSE(scalar);
  EXPECT_EQ(scalar.error(), "scalar.yaml: expected a mapping of parameters at the top level");
}

TEST(ParamsFile, GivenFileOnDiskWhenLoadedThenSameAsParsed) {
  const auto path = std::filesystem::temp_directory_path() / "sb_params_test.yaml";
  std::ofstream(path) << kGood;
  auto file = ParamsFile::load(path.string());
  ASSERT_TRUE(file);
  double gain = 0;
  file->read("gain", gain, 0, 10);
  EXPECT_DOUBLE_EQ(gain, 2.5);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace stereoball::params

namespace stereoball::params {
namespace {

// yaml-cpp keeps the first of two equal keys; the loader must refuse the file instead.
TEST(ParamsFile, GivenADuplicatedKeyWhenParsedThenTheErrorNamesFileKeyAndBothLines) {
  Demo demo;
  const auto error = load_demo(
      "gain: 2.5\nnested:\n  count: 7\n  count: 9\nenabled: true\nmode: b\n"
      "xyz: [1, 2, 3]\n",
      demo);
  ASSERT_FALSE(error.ok());
  EXPECT_EQ(error.error(), "demo.yaml: key 'nested.count' appears twice (lines 3 and 4)");
}

TEST(ParamsFile, GivenADuplicatedTopLevelKeyInAFileWhenLoadedThenItIsRefused) {
  const auto path = std::filesystem::temp_directory_path() / "sb_duplicate_key.yaml";
  std::ofstream(path) << kGood << "gain: 3.5\n";
  const auto file = ParamsFile::load(path.string());
  ASSERT_FALSE(file);
  EXPECT_EQ(file.error(), path.string() + ": key 'gain' appears twice (lines 1 and 7)");
  std::filesystem::remove(path);
}

TEST(YamlLoad, GivenEqualKeysInDifferentMappingsWhenCheckedThenNothingIsReported) {
  const auto root = parse_yaml("a: {x: 1}\nb: {x: 2}\nlist:\n  - {x: 1}\n  - {x: 2}\n", "t");
  ASSERT_TRUE(root) << root.error();
}

TEST(YamlLoad, GivenADuplicateInsideAListItemWhenCheckedThenThePathHasTheIndex) {
  const auto root = parse_yaml("list:\n  - {x: 1}\n  - x: 1\n    x: 2\n", "t");
  ASSERT_FALSE(root);
  EXPECT_EQ(root.error(), "t: key 'list[1].x' appears twice (lines 3 and 4)");
}

}  // namespace
}  // namespace stereoball::params
