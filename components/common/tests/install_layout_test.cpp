#include "common/util/install_layout.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace stereoball::paths {
namespace {
namespace fs = std::filesystem;

// A scratch folder holding one tree per search level, removed after each test.
class InstallLayout : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("sb_layout_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    roots_.env_config_dir = dir_ / "env";
    roots_.etc_dir = dir_ / "etc";
    roots_.share_dir = dir_ / "usr/share/stereoball";
    roots_.source_dir = dir_ / "src";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const fs::path& path, const std::string& text = "a: 1\n") {
    fs::create_directories(path.parent_path());
    std::ofstream(path) << text;
    return path;
  }

  fs::path dir_;
  SearchRoots roots_;
};

TEST_F(InstallLayout, EachLevelWinsOverTheLevelsBelowIt) {
  // Given tracker.yaml at every level
  const auto source = write(dir_ / "src/config/tracker.yaml");
  const auto share = write(dir_ / "usr/share/stereoball/config/tracker.yaml");
  const auto etc = write(dir_ / "etc/tracker.yaml");
  const auto env = write(dir_ / "env/tracker.yaml");
  // Then the environment wins, and removing each winner hands over to the next level
  EXPECT_EQ(find_config("tracker.yaml", roots_)->path, env);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->origin, "$STEREOBALL_CONFIG_DIR");
  fs::remove(env);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->path, etc);
  fs::remove(etc);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->path, share);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->origin, "installed files");
  fs::remove(share);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->path, source);
  EXPECT_EQ(find_config("tracker.yaml", roots_)->origin, "source tree");
}

TEST_F(InstallLayout, MissingEverywhereListsEveryPlaceTried) {
  // Given no tracker.yaml anywhere
  // When it is searched
  const auto found = find_config("tracker.yaml", roots_);
  // Then the error names each candidate, in order
  ASSERT_FALSE(found);
  const std::string& e = found.error();
  const auto env = e.find((dir_ / "env/tracker.yaml").string());
  const auto etc = e.find((dir_ / "etc/tracker.yaml").string());
  const auto share = e.find((dir_ / "usr/share/stereoball/config/tracker.yaml").string());
  const auto source = e.find((dir_ / "src/config/tracker.yaml").string());
  ASSERT_NE(env, std::string::npos) << e;
  ASSERT_NE(source, std::string::npos) << e;
  EXPECT_LT(env, etc);
  EXPECT_LT(etc, share);
  EXPECT_LT(share, source);
  EXPECT_NE(e.find("--config"), std::string::npos) << "says how to fix it: " << e;
}

TEST_F(InstallLayout, AnOverrideThatCannotBeReadIsAnErrorNotSkipped) {
  // Given an /etc override that is a folder, not a file, and a good installed file
  fs::create_directories(dir_ / "etc/tracker.yaml");
  write(dir_ / "usr/share/stereoball/config/tracker.yaml");
  // When searched, then the broken override is reported instead of silently falling through
  const auto found = find_config("tracker.yaml", roots_);
  ASSERT_FALSE(found);
  EXPECT_NE(found.error().find((dir_ / "etc/tracker.yaml").string()), std::string::npos);
  EXPECT_NE(found.error().find("a folder, not a file"), std::string::npos) << found.error();
}

TEST_F(InstallLayout, UnreadableFileIsAnErrorNamingIt) {
  if (geteuid() == 0) GTEST_SKIP() << "root reads any file: permission bits cannot be tested";
  const auto etc = write(dir_ / "etc/tracker.yaml");
  fs::permissions(etc, fs::perms::none);
  const auto found = find_config("tracker.yaml", roots_);
  ASSERT_FALSE(found);
  EXPECT_NE(found.error().find("cannot be read"), std::string::npos) << found.error();
}

TEST_F(InstallLayout, FoldersAreFoundLikeFiles) {
  // Given the scenarios folder only in the installed files
  fs::create_directories(dir_ / "usr/share/stereoball/config/scenarios");
  const auto found = find_config("scenarios", roots_);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->path, dir_ / "usr/share/stereoball/config/scenarios");
}

TEST_F(InstallLayout, ExplicitPathIsCheckedNotSearched) {
  write(dir_ / "etc/tracker.yaml");
  EXPECT_FALSE(check_explicit(dir_ / "nowhere.yaml"));
  EXPECT_NE(check_explicit(dir_ / "nowhere.yaml").error().find("nowhere.yaml: no such file"),
            std::string::npos);
  const auto given = write(dir_ / "mine.yaml");
  EXPECT_EQ(check_explicit(given)->path, given);
  EXPECT_EQ(check_explicit(given)->origin, "--config");
}

TEST_F(InstallLayout, InstalledProgramFindsShareFromBinOrLibexec) {
  // Given an unpacked package: usr/bin/stereoball and usr/libexec/stereoball/tracker
  fs::create_directories(dir_ / "usr/share/stereoball/config");
  fs::create_directories(dir_ / "usr/bin");
  fs::create_directories(dir_ / "usr/libexec/stereoball");
  const auto expected = fs::weakly_canonical(dir_ / "usr/share/stereoball");
  // When roots are derived from either program's location
  const auto from_bin = roots_for_executable(dir_ / "usr/bin/stereoball", {}, dir_ / "src");
  const auto from_libexec =
      roots_for_executable(dir_ / "usr/libexec/stereoball/tracker", {}, dir_ / "src");
  // Then both find the installed share folder, and neither may read the source tree
  EXPECT_EQ(from_bin.share_dir, expected);
  EXPECT_EQ(from_libexec.share_dir, expected);
  EXPECT_FALSE(from_bin.source_dir.has_value());
  EXPECT_FALSE(from_libexec.source_dir.has_value());
  EXPECT_EQ(data_root(from_bin).value(), expected);
}

TEST_F(InstallLayout, OnlyAProgramInItsBuildTreeFallsBackToTheSourceTree) {
  fs::create_directories(dir_ / "build/bin");
  fs::create_directories(dir_ / "elsewhere");
  const auto in_build =
      roots_for_executable(dir_ / "build/bin/tracker", {dir_ / "build/bin"}, dir_ / "src");
  const auto moved =
      roots_for_executable(dir_ / "elsewhere/tracker", {dir_ / "build/bin"}, dir_ / "src");
  EXPECT_EQ(in_build.source_dir, dir_ / "src");
  EXPECT_EQ(data_root(in_build).value(), dir_ / "src");
  EXPECT_FALSE(moved.source_dir.has_value());
  EXPECT_FALSE(data_root(moved));
}

}  // namespace
}  // namespace stereoball::paths
