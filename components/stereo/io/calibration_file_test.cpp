#include "stereo/io/calibration_file.hpp"

#include "stereo/core/synthetic_rig.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace stereoball::stereo {
namespace {

namespace fs = std::filesystem;

class CalibrationFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sb_stereo_io_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
            "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    calib_.rms_px = 0.31;
    calib_.per_pair_rms_px = {0.2, 0.3, 0.4};
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  // The good calibration's YAML with one top-level entry replaced by `replacement`.
  // Entries are "KEY: !!opencv-matrix" followed by lines indented by three spaces, or
  // "KEY: value" (plain string editing: GCC 12's <regex> trips -Wmaybe-uninitialized).
  std::string edited_yaml(const std::string& key, const std::string& replacement) {
    std::string yaml = calibration_to_yaml(calib_);
    const std::size_t begin = yaml.find("\n" + key + ":");
    if (begin == std::string::npos) return yaml;
    std::size_t end = yaml.find('\n', begin + 1);
    while (end != std::string::npos && yaml.compare(end + 1, 3, "   ") == 0) {
      end = yaml.find('\n', end + 1);
    }
    yaml.replace(begin, end == std::string::npos ? std::string::npos : end - begin,
                 "\n" + replacement);
    return yaml;
  }
  fs::path dir_;
  StereoCalibration calib_ = default_synthetic_rig().calibration();
};

TEST_F(CalibrationFileTest, GivenCalibrationWhenSavedAndLoadedThenIdentical) {
  // Given a calibration, When written to YAML and read back
  const std::string path = (dir_ / "calib.yaml").string();
  CalibrationFileInfo info;
  info.mean_rectified_row_error_px = 0.1;
  ASSERT_TRUE(save_calibration(path, calib_, info).ok());
  const auto loaded = load_calibration(path);
  // Then every field is the same
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  const StereoCalibration& c = loaded.value();
  EXPECT_EQ(c.image_size, calib_.image_size);
  EXPECT_EQ(c.k1, calib_.k1);
  EXPECT_EQ(c.d1, calib_.d1);
  EXPECT_EQ(c.k2, calib_.k2);
  EXPECT_EQ(c.d2, calib_.d2);
  EXPECT_EQ(c.r, calib_.r);
  EXPECT_EQ(c.t, calib_.t);
  EXPECT_EQ(c.r1, calib_.r1);
  EXPECT_EQ(c.r2, calib_.r2);
  EXPECT_EQ(c.p1, calib_.p1);
  EXPECT_EQ(c.p2, calib_.p2);
  EXPECT_EQ(c.q, calib_.q);
  EXPECT_EQ(c.rms_px, calib_.rms_px);
  EXPECT_EQ(c.per_pair_rms_px, calib_.per_pair_rms_px);
}

TEST_F(CalibrationFileTest, GivenNoDistortionWhenSavedThenLoadsAsZeros) {
  calib_.d1.clear();
  const std::string path = (dir_ / "nodist.yml").string();
  ASSERT_TRUE(save_calibration(path, calib_).ok());
  const auto loaded = load_calibration(path);
  ASSERT_TRUE(loaded.ok()) << loaded.error();
  EXPECT_EQ(loaded->d1, std::vector<double>(5, 0.0));
}

TEST_F(CalibrationFileTest, GivenMissingMatrixWhenLoadedThenErrorNamesFileAndField) {
  // Given a file without K2
  const std::string path = write("no_k2.yaml", edited_yaml("K2", ""));
  // When loaded
  const auto loaded = load_calibration(path);
  // Then the error names the file and K2
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().find(path), std::string::npos) << loaded.error();
  EXPECT_NE(loaded.error().find("K2: missing"), std::string::npos) << loaded.error();
}

TEST_F(CalibrationFileTest, GivenWronglySizedMatrixWhenLoadedThenErrorNamesFieldAndShape) {
  // Given P1 written as 3x3 instead of 3x4
  const std::string p1 =
      "P1: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., "
      "0., 0., 1. ]";
  const auto loaded = load_calibration(write("p1.yaml", edited_yaml("P1", p1)));
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().find("P1: expected 3x4, got 3x3"), std::string::npos) << loaded.error();
}

TEST_F(CalibrationFileTest, GivenWrongDistortionLengthWhenLoadedThenErrorNamesD1) {
  const std::string d1 =
      "D1: !!opencv-matrix\n   rows: 1\n   cols: 3\n   dt: d\n   data: [ 0.1, 0.2, 0.3 ]";
  const auto loaded = parse_calibration(edited_yaml("D1", d1));
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().find("D1: expected 1xN"), std::string::npos) << loaded.error();
}

TEST_F(CalibrationFileTest, GivenMissingImageSizeOrNonMatrixWhenParsedThenFieldNamed) {
  auto missing_width = parse_calibration(edited_yaml("image_width", ""));
  ASSERT_FALSE(missing_width.ok());
  EXPECT_NE(missing_width.error().find("image_width: missing"), std::string::npos);
  auto scalar_r = parse_calibration(edited_yaml("R", "R: 3"));
  ASSERT_FALSE(scalar_r.ok());
  EXPECT_NE(scalar_r.error().find("R:"), std::string::npos) << scalar_r.error();
}

TEST_F(CalibrationFileTest, GivenGarbledOrHugeMatrixHeaderWhenParsedThenRefusedBeforeAllocating) {
  // Given R2 headers that OpenCV would size its allocation from (the fuzzer's "rows:&3" asked
  // for 2^31 rows), a huge declared size, and a data list shorter than the header says
  const std::string data = "   dt: d\n   data: [ 1., 0., 0., 0., 1., 0., 0., 0., 1. ]";
  const auto garbled =
      parse_calibration(edited_yaml("R2", "R2: !!opencv-matrix\n   rows:&3\n   cols: 3\n" + data));
  const auto huge = parse_calibration(
      edited_yaml("R2", "R2: !!opencv-matrix\n   rows: 100000\n   cols: 100000\n" + data));
  const auto short_data =
      parse_calibration(edited_yaml("R2", "R2: !!opencv-matrix\n   rows: 3\n   cols: 4\n" + data));
  // Then each is refused with R2 named, and the good file still loads
  for (const auto* r : {&garbled, &huge, &short_data}) {
    ASSERT_FALSE(r->ok());
    EXPECT_NE(r->error().find("R2:"), std::string::npos) << r->error();
  }
  EXPECT_NE(huge.error().find("100000x100000 is not a calibration matrix size"), std::string::npos)
      << huge.error();
  EXPECT_NE(short_data.error().find("data has 9 values for 3x4"), std::string::npos)
      << short_data.error();
  EXPECT_TRUE(parse_calibration(calibration_to_yaml(calib_)).ok());
}

TEST_F(CalibrationFileTest, GivenTextAfterTheDocumentMarkerWhenParsedThenRefusedWithItsLine) {
  // Given the smallest text on which OpenCV 4.6's YAML reader loops forever (from fuzzing)
  const auto looped = parse_calibration("%YAML:1.0\n---a: t\nb: -\nc");
  // Then it is refused before OpenCV sees it, naming the line; "---" on its own line still loads
  ASSERT_FALSE(looped.ok());
  EXPECT_NE(looped.error().find("line 2: text after the document marker"), std::string::npos)
      << looped.error();
  EXPECT_TRUE(parse_calibration(calibration_to_yaml(calib_)).ok());
  // And a file over 1 MiB is refused without being parsed
  const auto big = load_calibration(write("big.yaml", std::string((1 << 20) + 1, ' ')));
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().find("larger than 1 MiB"), std::string::npos) << big.error();
}

TEST_F(CalibrationFileTest, GivenFuzzerFindingsWhenParsedThenErrorsNotCrashes) {
  // Given the calibration inputs the fuzzer crashed on (kept in its corpus): a garbled matrix
  // header, and text on which OpenCV's parser throws std::length_error
  for (const char* name : {"garbled-rows-header.yaml", "length-error-from-parser.yaml",
                           "parser-loop-after-document-marker.yaml"}) {
    const std::string path = std::string(SB_SOURCE_DIR) + "/tests/fuzz/corpus/calibration/" + name;
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path;
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    // When parsed, and when loaded as a file, Then each is an error (no exception escapes)
    EXPECT_FALSE(parse_calibration(text).ok()) << name;
    EXPECT_FALSE(load_calibration(path).ok()) << name;
  }
}

TEST_F(CalibrationFileTest, GivenInconsistentValuesWhenLoadedThenValidationNamesField) {
  // Given a well-formed file whose T is all zeros
  const std::string t =
      "T: !!opencv-matrix\n   rows: 3\n   cols: 1\n   dt: d\n   data: [ 0., 0., 0. ]";
  const auto loaded = parse_calibration(edited_yaml("T", t));
  ASSERT_FALSE(loaded.ok());
  EXPECT_NE(loaded.error().find("T: must be finite and non-zero"), std::string::npos)
      << loaded.error();
}

TEST_F(CalibrationFileTest, GivenMissingOrGarbageFileWhenLoadedThenClearErrorNoCrash) {
  const auto missing = load_calibration((dir_ / "nope.yaml").string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("no such calibration file"), std::string::npos);
  const auto garbage = load_calibration(write("garbage.yaml", "%YAML:1.0\n: : [ {\n\x01\x02"));
  EXPECT_FALSE(garbage.ok());
  EXPECT_FALSE(garbage.error().empty());
  const auto empty = load_calibration(write("empty.yaml", ""));
  EXPECT_FALSE(empty.ok());
}

TEST_F(CalibrationFileTest, GivenInvalidCalibrationWhenSavedThenRefused) {
  calib_.k1(0, 0) = 0.0;
  const auto error = save_calibration((dir_ / "bad.yaml").string(), calib_);
  ASSERT_FALSE(error.ok());
  EXPECT_NE(error.error().find("K1"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "bad.yaml"));
}

TEST(PairList, GivenOpenCvSampleListWhenLoadedThenThirteenExistingPairs) {
  const auto pairs =
      load_pair_list(std::string(SB_SHARED_DATA_DIR) + "/opencv-samples/stereo_calib.xml");
  ASSERT_TRUE(pairs.ok()) << pairs.error();
  ASSERT_EQ(pairs->size(), 13u);
  EXPECT_NE(pairs->front().first.find("left01.jpg"), std::string::npos);
  EXPECT_NE(pairs->front().second.find("right01.jpg"), std::string::npos);
  for (const auto& [l, r] : pairs.value()) {
    EXPECT_TRUE(fs::exists(l)) << l;
    EXPECT_TRUE(fs::exists(r)) << r;
  }
}

TEST_F(CalibrationFileTest, GivenOddOrMissingListWhenLoadedThenError) {
  const auto odd =
      load_pair_list(write("odd.xml",
                           "<?xml version=\"1.0\"?>\n<opencv_storage>\n<imagelist>\n\"a.jpg\"\n"
                           "\"b.jpg\"\n\"c.jpg\"\n</imagelist>\n</opencv_storage>\n"));
  ASSERT_FALSE(odd.ok());
  EXPECT_NE(odd.error().find("odd number of images"), std::string::npos) << odd.error();
  EXPECT_FALSE(load_pair_list((dir_ / "none.xml").string()).ok());
}

// The pair list goes to the same OpenCV YAML reader as the calibration, so it gets the same
// checks first: the input that made OpenCV 4.6 loop forever, and the size bound.
TEST_F(CalibrationFileTest, GivenPairListOpenCvWouldHangOnWhenLoadedThenRefusedWithLine) {
  const auto hang = load_pair_list(write("hang.yaml", "%YAML:1.0\n---a: t\nb: -\nc"));
  ASSERT_FALSE(hang.ok());
  EXPECT_NE(hang.error().find("line 2: text after the document marker"), std::string::npos)
      << hang.error();
  const auto big = load_pair_list(write("big.yaml", std::string((1 << 20) + 1, '#')));
  ASSERT_FALSE(big.ok());
  EXPECT_NE(big.error().find("larger than 1 MiB (a pair list"), std::string::npos) << big.error();
}

}  // namespace
}  // namespace stereoball::stereo

namespace stereoball::stereo {
namespace {

TEST(ShippedCalibration, GivenRepoCalibrationOfSamplePairsWhenLoadedThenValidAndAccurate) {
  // Given the calibration committed under config/calibration (OpenCV sample pairs)
  const auto c = load_calibration(std::string(SB_SOURCE_DIR) +
                                  "/config/calibration/opencv_samples_stereo.yaml");
  // Then it loads, is for 640x480 and records a sub-0.5 px RMS for all 13 pairs
  ASSERT_TRUE(c.ok()) << c.error();
  EXPECT_EQ(c->image_size, cv::Size(640, 480));
  EXPECT_LT(c->rms_px, 0.5);
  EXPECT_EQ(c->per_pair_rms_px.size(), 13u);
}

}  // namespace
}  // namespace stereoball::stereo
