// The installable package: `cpack -G DEB` builds stereoball_<version>_amd64.deb with
// dpkg-shlibdeps dependencies; unpacked into an empty folder it runs the demo from its own files
// and finds its configuration by the documented search order.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "process.hpp"

namespace sb = stereoball;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// One package and one unpacked root for every test of this file (building it takes a while).
class Package : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!SB_PACKAGE_TOOLS) return;
    out_dir_ = new std::string(sb::testing::temp_dir());
    const auto [code, output] =
        sb::testing::run({SB_CPACK, "--config", std::string(SB_BUILD_DIR) + "/CPackConfig.cmake",
                          "-G", "DEB", "-B", *out_dir_},
                         480s);
    cpack_output_ = new std::string(output);
    deb_ = new std::string(*out_dir_ + "/stereoball_" SB_PROJECT_VERSION "_amd64.deb");
    root_ = new std::string(*out_dir_ + "/root");
    if (code == 0 && fs::exists(*deb_)) {
      sb::testing::run({SB_DPKG_DEB, "-x", *deb_, *root_}, 120s);
    }
  }
  void SetUp() override {
    if (!SB_PACKAGE_TOOLS) {
      GTEST_SKIP() << "dpkg-deb / dpkg-shlibdeps missing (Debian packages dpkg-dev and file; "
                      "`bash run.sh test` installs them)";
    }
    ASSERT_TRUE(fs::exists(*deb_)) << "cpack did not write " << *deb_ << ":\n" << *cpack_output_;
  }
  static std::string field(const std::string& name) {
    auto [code, out] = sb::testing::run({SB_DPKG_DEB, "-f", *deb_, name}, 30s);
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
  }
  static std::string root(const std::string& rel) { return *root_ + "/" + rel; }
  // Runs an installed program with no trace of the build: the source tree's config folder
  // and Cyclone configuration (set by ctest) are removed from its environment.
  static std::vector<std::string> clean_env(std::vector<std::string> argv,
                                            const std::vector<std::string>& keep = {}) {
    std::vector<std::string> cmd{
        "/usr/bin/env",  "-u", "CYCLONEDDS_URI", "-u", "STEREOBALL_CONFIG_DIR", "-u",
        "SB_SOURCE_DIR", "-u", "SB_BIN_DIR"};
    cmd.insert(cmd.end(), keep.begin(), keep.end());
    cmd.insert(cmd.end(), argv.begin(), argv.end());
    return cmd;
  }

  static inline std::string* out_dir_ = nullptr;
  static inline std::string* cpack_output_ = nullptr;
  static inline std::string* deb_ = nullptr;
  static inline std::string* root_ = nullptr;
};

TEST_F(Package, ControlFieldsNameTheLibrariesTheProgramsLink) {
  EXPECT_EQ(field("Package"), "stereoball");
  EXPECT_EQ(field("Version"), SB_PROJECT_VERSION);
  EXPECT_EQ(field("Architecture"), "amd64");
  // From dpkg-shlibdeps: the run-time libraries, not the -dev packages
  const std::string depends = field("Depends");
  for (const char* lib : {"libddsc0debian", "libopencv-core406", "libopencv-imgproc406",
                          "libyaml-cpp0.7", "libzstd1", "libc6"}) {
    EXPECT_NE(depends.find(lib), std::string::npos) << lib << " missing from: " << depends;
  }
  EXPECT_EQ(depends.find("-dev"), std::string::npos) << depends;
}

TEST_F(Package, InstallsProgramsDataAndBothSystemdRoles) {
  for (const char* rel :
       {"usr/bin/stereoball", "usr/libexec/stereoball/stereoball-demo",
        "usr/libexec/stereoball/stereoball-launch", "usr/libexec/stereoball/ball_detector",
        "usr/libexec/stereoball/tracker", "usr/libexec/stereoball/motion_controller",
        "usr/libexec/stereoball/simulator", "usr/libexec/stereoball/camera_server",
        "usr/share/stereoball/config/tracker.yaml",
        "usr/share/stereoball/config/scenarios/ball_still.yaml",
        "usr/share/stereoball/config/cyclonedds/lan.xml", "usr/share/stereoball/deploy/robot.yaml",
        "usr/share/stereoball/idl/stereoball.idl",
        "usr/lib/systemd/system/stereoball-robot.service",
        "usr/lib/systemd/system/stereoball-workstation.service"}) {
    EXPECT_TRUE(fs::exists(root(rel))) << rel;
  }
  // Tests and test helpers stay out of the package.
  EXPECT_FALSE(fs::exists(root("usr/libexec/stereoball/sb_test_peer")));
  EXPECT_FALSE(fs::exists(root("usr/libexec/stereoball/sb_fastdds_listener")));
  // Each role runs the installed launcher with its own profile.
  std::ifstream unit(root("usr/lib/systemd/system/stereoball-workstation.service"));
  const std::string text((std::istreambuf_iterator<char>(unit)), {});
  EXPECT_NE(text.find("ExecStart=/usr/bin/stereoball launch ${STEREOBALL_PROFILE}"),
            std::string::npos);
  EXPECT_NE(text.find("STEREOBALL_PROFILE=workstation"), std::string::npos);
}

TEST_F(Package, DemoRunsFromTheUnpackedFilesOnly) {
  // Given the unpacked package and no source or build tree in the environment
  const std::string report = sb::testing::temp_dir();
  // When the demo runs a short scenario
  const auto [code, output] = sb::testing::run(
      clean_env({root("usr/bin/stereoball"), "demo", "--scenario", "ball_still", "--duration", "4",
                 "--out", report, "--domain", std::to_string(sb::testing::test_domain())}),
      240s);
  // Then it completes, with every node reading the installed parameters
  ASSERT_EQ(code, 0) << output;
  std::ifstream log(report + "/stereoball.log");
  const std::string node_log((std::istreambuf_iterator<char>(log)), {});
  for (const char* file :
       {"simulator.yaml", "ball_detector.yaml", "tracker.yaml", "motion_controller.yaml"}) {
    const std::string used = "parameters from " +
                             fs::weakly_canonical(root("usr/share/stereoball/config")).string() +
                             "/" + file + " (installed files)";
    EXPECT_NE(node_log.find(used), std::string::npos) << used << "\n" << node_log;
  }
  EXPECT_EQ(node_log.find(SB_SOURCE_DIR), std::string::npos) << "a source path leaked:\n"
                                                             << node_log;
  EXPECT_EQ(output.find(SB_SOURCE_DIR), std::string::npos) << output;
}

TEST_F(Package, ConfigSearchOrderOfAnInstalledNode) {
  const std::string tracker = root("usr/libexec/stereoball/tracker");
  const std::string domain = std::to_string(sb::testing::test_domain());
  // $STEREOBALL_CONFIG_DIR comes first: a broken file there is reported, naming it
  const std::string env_dir = sb::testing::temp_dir();
  std::ofstream(env_dir + "/tracker.yaml") << "no_such_key: 1\n";
  auto [env_code, env_out] = sb::testing::run(
      clean_env({tracker, "--domain", domain}, {"STEREOBALL_CONFIG_DIR=" + env_dir}), 30s);
  EXPECT_NE(env_code, 0);
  EXPECT_NE(env_out.find(env_dir + "/tracker.yaml"), std::string::npos) << env_out;
  EXPECT_NE(env_out.find("key '"), std::string::npos) << "names the bad key: " << env_out;
  // An explicit --config that does not exist: named, and nothing else is tried
  auto [missing_code, missing_out] = sb::testing::run(
      clean_env({tracker, "--domain", domain, "--config", "/nonexistent.yaml"}), 30s);
  EXPECT_NE(missing_code, 0);
  EXPECT_NE(missing_out.find("/nonexistent.yaml"), std::string::npos) << missing_out;
  // A folder where the file should be (unreadable as a file): an error, not a fallback
  const std::string bad_dir = sb::testing::temp_dir();
  fs::create_directories(bad_dir + "/tracker.yaml");
  auto [bad_code, bad_out] = sb::testing::run(
      clean_env({tracker, "--domain", domain}, {"STEREOBALL_CONFIG_DIR=" + bad_dir}), 30s);
  EXPECT_NE(bad_code, 0);
  EXPECT_NE(bad_out.find("cannot be read"), std::string::npos) << bad_out;
}

}  // namespace
