#include "common/util/install_layout.hpp"

#include <grp.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
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

// The search's error for roots_, as the unprivileged user `nobody` (uid/gid 65534) sees it when
// this test runs as root (root reads any file, so permission bits mean nothing to it): the
// search runs in a child process that drops its privileges first. "" when the file was found.
std::string search_error_as_nobody(const SearchRoots& roots) {
  int out[2];
  if (::pipe(out) != 0) return "pipe failed";
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(out[0]);
    std::string text;
    if (::setgroups(0, nullptr) != 0 || ::setresgid(65534, 65534, 65534) != 0 ||
        ::setresuid(65534, 65534, 65534) != 0 || ::geteuid() == 0) {
      text = "could not drop root privileges to uid 65534";
    } else if (const auto found = find_config("tracker.yaml", roots); !found) {
      text = found.error();
    }
    if (::write(out[1], text.data(), text.size()) < 0) ::_exit(2);
    ::_exit(0);
  }
  ::close(out[1]);
  std::string text;
  char buffer[512];
  for (ssize_t n; (n = ::read(out[0], buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  ::close(out[0]);
  int status = 0;
  ::waitpid(child, &status, 0);
  return text;
}

TEST_F(InstallLayout, UnreadableFileIsAnErrorNamingIt) {
  // Given an /etc override nobody may read
  const auto etc = write(dir_ / "etc/tracker.yaml");
  fs::permissions(etc, fs::perms::none);
  // (the folders on the way open to everyone whatever the umask, so only the file is refused)
  const auto open = fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                    fs::perms::others_read | fs::perms::others_exec;
  for (const auto& folder : {dir_, dir_ / "etc"}) fs::permissions(folder, open);
  // When searched by an unprivileged user (this process, or as root a child that is `nobody`)
  std::string error;
  if (::geteuid() == 0) {
    error = search_error_as_nobody(roots_);
  } else {
    const auto found = find_config("tracker.yaml", roots_);
    ASSERT_FALSE(found);
    error = found.error();
  }
  // Then the error names the file and says it cannot be read
  EXPECT_NE(error.find(etc.string()), std::string::npos) << error;
  EXPECT_NE(error.find("cannot be read"), std::string::npos) << error;
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
