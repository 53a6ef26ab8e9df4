// The deployment's DDS configuration (common/util/deployment.hpp): the roles' settings file,
// the profile's file by the configuration search order, and the order of the rules.
#include "common/util/deployment.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace stereoball::deployment {
namespace {
namespace fs = std::filesystem;

fs::path write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
  return path;
}

// Inputs whose profile lookup answers from the repository's own deploy/ and config/.
DdsConfigInputs repository_inputs() {
  DdsConfigInputs in;
  in.profile_dds = [](const std::string& profile) {
    paths::SearchRoots roots;
    roots.source_dir = fs::path(SB_SOURCE_DIR);
    return profile_dds_file(profile, roots);
  };
  return in;
}

TEST(EnvFile, ReadsAssignmentsCommentsAndQuotes) {
  // Given a settings file as an administrator writes it
  const auto parsed = parse_env_file(
      "# comment\n\n; other comment\nSTEREOBALL_IFACE=eth0\n  STEREOBALL_PEER = 10.0.0.2  \n"
      "STEREOBALL_DEPLOYMENT=\"robot 1\"\nSTEREOBALL_PARTITION='p'\nEMPTY=\n",
      "stereoball.env");
  // Then every assignment is read, in order, without quotes and surrounding blanks
  ASSERT_TRUE(parsed) << parsed.error();
  ASSERT_EQ(parsed->size(), 5u);
  EXPECT_EQ((*parsed)[0], std::make_pair(std::string("STEREOBALL_IFACE"), std::string("eth0")));
  EXPECT_EQ((*parsed)[1].second, "10.0.0.2");
  EXPECT_EQ((*parsed)[2].second, "robot 1");
  EXPECT_EQ((*parsed)[3].second, "p");
  EXPECT_EQ((*parsed)[4].second, "");
}

TEST(EnvFile, BadLinesNameFileAndLine) {
  struct Case {
    std::string text, expected;
  };
  for (const Case& c : {Case{"A=1\nnot an assignment\n", "f.env: line 2: expected NAME=VALUE"},
                        Case{"1A=2\n", "f.env: line 1: '1A' is not a variable name"},
                        Case{"A-B=2\n", "'A-B' is not a variable name"},
                        Case{"A=\"open\n", "line 1: quote opened and not closed"}}) {
    const auto parsed = parse_env_file(c.text, "f.env");
    ASSERT_FALSE(parsed) << c.text;
    EXPECT_NE(parsed.error().find(c.expected), std::string::npos) << parsed.error();
  }
}

TEST(DdsConfig, ExplicitCycloneUriWins) {
  // Given CYCLONEDDS_URI set, and a profile named too
  DdsConfigInputs in = repository_inputs();
  in.cyclonedds_uri = "file:///mine.xml";
  in.profile = "robot";
  in.lan_interface = true;
  // Then the operator's choice is used as given
  const auto config = resolve_dds_config(in);
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->uri, "file:///mine.xml");
  EXPECT_TRUE(config->from_environment);
  EXPECT_EQ(config->origin, "$CYCLONEDDS_URI");
}

TEST(DdsConfig, WithoutAnyHintItIsTheAllInOneProfilesLoopback) {
  // Given nothing set (a developer's shell beside `stereoball launch all-in-one`)
  const auto config = resolve_dds_config(repository_inputs());
  // Then the tool uses the file the all-in-one profile gives its nodes
  ASSERT_TRUE(config) << config.error();
  EXPECT_EQ(config->profile, "all-in-one");
  EXPECT_EQ(config->uri, file_uri(fs::path(SB_SOURCE_DIR) / "config/cyclonedds/loopback.xml"));
  EXPECT_NE(config->origin.find("neither STEREOBALL_PROFILE nor STEREOBALL_IFACE"),
            std::string::npos)
      << config->origin;
  EXPECT_FALSE(config->from_environment);
}

TEST(DdsConfig, AnInterfaceMeansTheLanConfigurationAndAProfileNamesItsOwn) {
  // Given STEREOBALL_IFACE set (every LAN profile needs it) and no profile
  DdsConfigInputs in = repository_inputs();
  in.lan_interface = true;
  const auto lan = resolve_dds_config(in);
  ASSERT_TRUE(lan) << lan.error();
  EXPECT_EQ(lan->uri, file_uri(fs::path(SB_SOURCE_DIR) / "config/cyclonedds/lan.xml"));
  // When the profile is named, its file is used whatever the interface says
  in.profile = "all-in-one";
  in.profile_source = "STEREOBALL_PROFILE in /etc/stereoball/stereoball.env";
  const auto named = resolve_dds_config(in);
  ASSERT_TRUE(named) << named.error();
  EXPECT_EQ(named->uri, file_uri(fs::path(SB_SOURCE_DIR) / "config/cyclonedds/loopback.xml"));
  EXPECT_NE(named->origin.find("STEREOBALL_PROFILE in /etc/stereoball/stereoball.env"),
            std::string::npos);
  // And an unknown profile is an error naming it, not a silent default
  in.profile = "robto";
  const auto unknown = resolve_dds_config(in);
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().find("profile 'robto' not found"), std::string::npos)
      << unknown.error();
}

TEST(DdsConfig, EveryShippedProfileButAllInOneUsesTheLanFile) {
  // The default for a host with STEREOBALL_IFACE (profile robot) is right for every LAN
  // profile only while they share one file: a new profile with another breaks this test.
  paths::SearchRoots roots;
  roots.source_dir = fs::path(SB_SOURCE_DIR);
  for (const auto& entry : fs::directory_iterator(fs::path(SB_SOURCE_DIR) / "deploy")) {
    if (entry.path().extension() != ".yaml") continue;
    const std::string name = entry.path().stem().string();
    const auto found = profile_dds_file(name, roots);
    ASSERT_TRUE(found) << name << ": " << found.error();
    EXPECT_EQ(fs::path(found->file).filename(), name == "all-in-one" ? "loopback.xml" : "lan.xml")
        << name;
  }
}

TEST(DdsConfig, ProfileFileFollowsTheConfigSearchOrder) {
  // Given an unpacked package and an administrator's copy of loopback.xml in /etc/stereoball
  const fs::path dir = fs::temp_directory_path() / ("sb_deploy_" + std::to_string(getpid()));
  fs::remove_all(dir);
  write(dir / "usr/share/stereoball/deploy/all-in-one.yaml",
        "cyclonedds: \"{config}/cyclonedds/loopback.xml\"\nnodes: []\n");
  write(dir / "usr/share/stereoball/deploy/bare.yaml", "nodes: []\n");
  const auto shipped = write(dir / "usr/share/stereoball/config/cyclonedds/loopback.xml", "<x/>");
  paths::SearchRoots roots;
  roots.share_dir = dir / "usr/share/stereoball";
  roots.etc_dir = dir / "etc/stereoball";
  auto found = profile_dds_file("all-in-one", roots);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->file, shipped.string());
  EXPECT_EQ(found->origin, "installed files");
  const auto local = write(dir / "etc/stereoball/cyclonedds/loopback.xml", "<y/>");
  found = profile_dds_file("all-in-one", roots);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->file, local.string());
  // A profile naming no file leaves Cyclone's defaults
  found = profile_dds_file("bare", roots);
  ASSERT_TRUE(found) << found.error();
  EXPECT_EQ(found->file, "");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace stereoball::deployment
