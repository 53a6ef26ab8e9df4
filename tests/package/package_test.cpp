// The installable package: `cpack -G DEB` builds stereoball_<version>_amd64.deb with
// dpkg-shlibdeps dependencies; unpacked into an empty folder it runs the demo from its own files
// and finds its configuration by the documented search order; both systemd roles' command lines
// run as an unprivileged user, and their sandboxing settings are in the units.

#include <grp.h>
#include <gtest/gtest.h>
#include <pwd.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>

#include <thread>

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

// "Key=value" lines of a unit file (the last wins, as in systemd for single-valued keys).
std::map<std::string, std::string> unit_settings(const std::string& path) {
  std::ifstream in(path);
  std::map<std::string, std::string> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#' || line[0] == '[') continue;
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = line.substr(0, eq), value = line.substr(eq + 1);
    // Environment= may appear more than once; keep each variable apart.
    if (key == "Environment") {
      const auto veq = value.find('=');
      out["Environment:" + value.substr(0, veq)] = value.substr(veq + 1);
    } else {
      out[key] = value;
    }
  }
  return out;
}

std::vector<std::string> split_words(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

// A uid and gid no account on this machine uses (the package's `stereoball` user stands in).
std::pair<uid_t, gid_t> unused_ids() {
  for (uid_t id = 61234; id < 61434; ++id) {
    if (!getpwuid(id) && !getgrgid(id)) return {id, id};
  }
  return {0, 0};
}

TEST_F(Package, BothRolesSandboxedInTheirUnits) {
  for (const char* role : {"robot", "workstation"}) {
    const auto unit =
        unit_settings(root(std::string("usr/lib/systemd/system/stereoball-") + role + ".service"));
    // A dedicated user without privileges, in the sandbox deploy/README.md describes
    EXPECT_EQ(unit.at("User"), "stereoball") << role;
    for (const auto& [key, value] : std::map<std::string, std::string>{
             {"NoNewPrivileges", "yes"},
             {"ProtectSystem", "strict"},
             {"ProtectHome", "yes"},
             {"PrivateTmp", "yes"},
             {"CapabilityBoundingSet", ""},
             {"StateDirectory", "stereoball"},
             {"LogsDirectory", "stereoball"},
             {"RestrictAddressFamilies", "AF_INET AF_INET6 AF_UNIX AF_NETLINK"},
             // Real-time priority set by systemd before it drops to the user (deploy/README.md)
             {"CPUSchedulingPolicy", "fifo"},
             {"CPUSchedulingPriority", "20"},
             {"RestrictRealtime", "yes"}}) {
      ASSERT_TRUE(unit.count(key)) << role << ": " << key << " missing";
      EXPECT_EQ(unit.at(key), value) << role << ": " << key;
    }
  }
  // systemd's own rating of the sandbox (issue 39: at most 4.0; 9.6 as root, unrestricted)
  if (fs::exists("/usr/bin/systemd-analyze")) {
    for (const char* role : {"robot", "workstation"}) {
      const std::string unit =
          root(std::string("usr/lib/systemd/system/stereoball-") + role + ".service");
      auto [code, out] =
          sb::testing::run({"/usr/bin/systemd-analyze", "security", "--offline=true", unit}, 60s);
      std::smatch level;
      ASSERT_TRUE(std::regex_search(out, level,
                                    std::regex("Overall exposure level for [^:]+: "
                                               "([0-9]+\\.[0-9])")))
          << role << ":\n"
          << out;
      EXPECT_LE(std::stod(level[1]), 4.0) << role << ":\n" << out;
    }
  } else {
    std::cout << "systemd-analyze missing (Debian package systemd): sandbox rating not checked\n";
  }
  // Cameras: the robot reaches V4L2 devices through the group video, and no other device
  EXPECT_EQ(unit_settings(root("usr/lib/systemd/system/stereoball-robot.service"))
                .at("SupplementaryGroups"),
            "video");
  // The package creates the user: postinst, and adduser among the dependencies
  EXPECT_NE(field("Depends").find("adduser"), std::string::npos) << field("Depends");
  const std::string control = sb::testing::temp_dir();
  ASSERT_EQ(sb::testing::run({SB_DPKG_DEB, "-e", *deb_, control}, 30s).first, 0);
  const std::string postinst = control + "/postinst";
  ASSERT_TRUE(fs::exists(postinst));
  EXPECT_EQ(access(postinst.c_str(), X_OK), 0) << "postinst is not executable";
  std::ifstream in(postinst);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  for (const char* step : {"adduser --system --group", "adduser stereoball video",
                           "chown stereoball:stereoball \"$key\"", "chmod 0600 \"$key\""}) {
    EXPECT_NE(text.find(step), std::string::npos) << step << " missing from postinst";
  }
  auto [syntax, why] = sb::testing::run({"/bin/sh", "-n", postinst}, 10s);
  EXPECT_EQ(syntax, 0) << why;
}

// Given the unpacked package, an unprivileged user (no account: a free uid stands in for the
// package's `stereoball` user, with the group video), a settings file as
// /etc/stereoball/stereoball.env and a key file owned by that user (mode 0600), when each role's
// ExecStart runs as that user (no capabilities, no new privileges, the state folder as working
// directory, logs in a folder of its own), then both launchers run every node of their profile
// without an exit, an e-stop run by the same user (no DDS configuration given) reaches the
// robot's holders, and both stop cleanly on SIGTERM.
TEST_F(Package, BothRolesRunTheirUnitsCommandLinesAsAnUnprivilegedUser) {
  if (geteuid() != 0) GTEST_SKIP() << "needs root to switch to an unprivileged user (setpriv)";
  if (!fs::exists("/usr/bin/setpriv")) GTEST_SKIP() << "/usr/bin/setpriv missing (util-linux)";
  const auto [uid, gid] = unused_ids();
  ASSERT_NE(uid, 0u) << "no free uid in 61234..61433";
  // The unpacked package must be reachable by that user (mkdtemp makes 0700 folders).
  ASSERT_EQ(chmod(out_dir_->c_str(), 0755), 0);
  const std::string home = sb::testing::temp_dir();  // stands in for /var/lib/stereoball
  const std::string logs = home + "/log";            // stands in for /var/log/stereoball
  fs::create_directories(logs);
  ASSERT_EQ(chmod(home.c_str(), 0750), 0);
  ASSERT_EQ(chown(home.c_str(), uid, gid), 0);
  ASSERT_EQ(chown(logs.c_str(), uid, gid), 0);
  std::vector<std::string> as_user{"/usr/bin/setpriv", "--reuid=" + std::to_string(uid),
                                   "--regid=" + std::to_string(gid)};
  if (const group* video = getgrnam("video")) {
    as_user.push_back("--groups=" + std::to_string(video->gr_gid));
  } else {
    as_user.push_back("--clear-groups");
  }
  for (const char* arg : {"--no-new-privs", "--inh-caps=-all", "--bounding-set=-all", "--",
                          "/bin/sh", "-c", "cd \"$0\" && exec \"$@\""}) {
    as_user.emplace_back(arg);
  }
  as_user.push_back(home);
  const std::string env_file = home + "/stereoball.env";
  const std::string key = home + "/deployment.key";
  const std::string partition = sb::testing::unique_partition();
  std::ofstream(env_file) << "# as /etc/stereoball/stereoball.env\nSTEREOBALL_IFACE=lo\n"
                          << "STEREOBALL_PEER=127.0.0.1\nSTEREOBALL_DOMAIN="
                          << sb::testing::test_domain() << "\nSTEREOBALL_KEY_FILE=" << key
                          << "\nSTEREOBALL_DEPLOYMENT=" << partition
                          << "\nSTEREOBALL_PARTITION=" << partition << "\n";
  // What systemd's environment holds: the settings file, no trace of the build or the test.
  auto user_cmd = [&](std::vector<std::string> argv) {
    std::vector<std::string> cmd = as_user;
    for (const char* a : {"/usr/bin/env", "-u", "CYCLONEDDS_URI", "-u", "STEREOBALL_CONFIG_DIR",
                          "-u", "SB_SOURCE_DIR", "-u", "SB_BIN_DIR", "-u", "STEREOBALL_PROFILE",
                          "-u", "STEREOBALL_KEY_FILE", "-u", "STEREOBALL_PARTITION"}) {
      cmd.emplace_back(a);
    }
    cmd.push_back("STEREOBALL_ENV_FILE=" + env_file);
    cmd.insert(cmd.end(), argv.begin(), argv.end());
    return cmd;
  };
  // The key, made by the user itself: theirs, mode 0600
  {
    auto [code, out] = sb::testing::run(
        user_cmd({root("usr/bin/stereoball"), "keys", "init", "--file", key}), 30s);
    ASSERT_EQ(code, 0) << out;
    struct stat st {};
    ASSERT_EQ(stat(key.c_str(), &st), 0);
    EXPECT_EQ(st.st_uid, uid);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
  }
  std::map<std::string, sb::testing::Process> launchers;
  std::map<std::string, std::string> node_logs;
  for (const char* role : {"robot", "workstation"}) {
    const auto unit =
        unit_settings(root(std::string("usr/lib/systemd/system/stereoball-") + role + ".service"));
    // The unit's command line, with the unpacked package and the stand-in folders
    std::vector<std::string> argv;
    for (std::string word : split_words(unit.at("ExecStart"))) {
      if (word == "${STEREOBALL_PROFILE}") word = unit.at("Environment:STEREOBALL_PROFILE");
      if (word == "/usr/bin/stereoball") word = root("usr/bin/stereoball");
      if (word.rfind("/var/log/stereoball/", 0) == 0) {
        word = logs + "/" + word.substr(std::string("/var/log/stereoball/").size());
        node_logs[role] = word;
      }
      argv.push_back(word);
    }
    ASSERT_TRUE(node_logs.count(role))
        << role << ": ExecStart logs elsewhere: " << unit.at("ExecStart");
    launchers.emplace(role, sb::testing::Process::start(user_cmd(argv)));
  }
  // Every node of both profiles started, and none exited, for a few seconds
  const std::map<std::string, std::vector<std::string>> nodes{
      {"robot", {"simulator", "motion_controller"}}, {"workstation", {"ball_detector", "tracker"}}};
  for (auto& [role, launcher] : launchers) {
    for (const auto& node : nodes.at(role)) {
      EXPECT_TRUE(launcher.wait_for_output(node + ": started", 30s)) << role << ":\n"
                                                                     << launcher.output();
    }
  }
  std::this_thread::sleep_for(6s);
  for (auto& [role, launcher] : launchers) {
    EXPECT_TRUE(launcher.running()) << role << ":\n" << launcher.output();
    EXPECT_EQ(launcher.output().find("exited with code"), std::string::npos) << role << ":\n"
                                                                             << launcher.output();
  }
  // The operator's stop, as the same user with nothing but the settings file, reaches the robot
  auto [code, out] = sb::testing::run(user_cmd({root("usr/bin/stereoball"), "estop", "engage",
                                                "--reason", "package test", "--wait", "10"}),
                                      60s);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("cyclonedds/lan.xml (profile robot"), std::string::npos) << out;
  std::smatch readers;
  ASSERT_TRUE(std::regex_search(out, readers, std::regex("delivered to ([0-9]+) reader"))) << out;
  EXPECT_GE(std::stoi(readers[1]), 2) << out;
  for (auto& [role, launcher] : launchers) {
    launcher.signal(SIGTERM);
    EXPECT_EQ(launcher.wait_for_exit(20s), std::optional<int>(0)) << role << ":\n"
                                                                  << launcher.output();
    // The log is the user's, in the folder the unit gives it
    struct stat st {};
    ASSERT_EQ(stat(node_logs[role].c_str(), &st), 0) << node_logs[role];
    EXPECT_EQ(st.st_uid, uid) << node_logs[role];
  }
}

}  // namespace
