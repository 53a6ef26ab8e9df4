// The deployment key file: permissions, format errors, rotation.
#include "common/auth/key_file.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace sa = stereoball::auth;
namespace fs = std::filesystem;

namespace {

constexpr int64_t kNowNs = 1'800'000'000'000'000'000;
constexpr int64_t kSecondNs = 1'000'000'000;

class KeyFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("sb_keys_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    path_ = (dir_ / "deployment.key").string();
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write_raw(const std::string& text, mode_t mode) {
    std::ofstream(path_) << text;
    ::chmod(path_.c_str(), mode);
  }
  fs::path dir_;
  std::string path_;
};

}  // namespace

TEST_F(KeyFileTest, SavedWithMode0600AndReadBack) {
  const sa::Keyring ring = sa::new_keyring();
  ASSERT_TRUE(sa::save_key_file(path_, ring).ok());
  struct stat st {};
  ASSERT_EQ(::stat(path_.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  auto loaded = sa::load_key_file(path_);
  ASSERT_TRUE(loaded) << loaded.error();
  ASSERT_EQ(loaded->keys.size(), 1u);
  EXPECT_EQ(loaded->keys[0].key, ring.keys[0].key);
  EXPECT_TRUE(loaded->keys[0].signs);
}

// Given a key file owned by the service user, when root rewrites it (a rotation run as root),
// then the new file still belongs to that user (the nodes run as it and must read it).
TEST_F(KeyFileTest, RewritingKeepsTheOwner) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to give the file to another user";
  ASSERT_TRUE(sa::save_key_file(path_, sa::new_keyring()).ok());
  const uid_t service_uid = 61299;
  ASSERT_EQ(::chown(path_.c_str(), service_uid, service_uid), 0);
  auto ring = sa::load_key_file(path_);
  ASSERT_TRUE(ring) << ring.error();
  ASSERT_TRUE(sa::save_key_file(path_, sa::rotate(*ring, kNowNs, 600 * kSecondNs)).ok());
  struct stat st {};
  ASSERT_EQ(::stat(path_.c_str(), &st), 0);
  EXPECT_EQ(st.st_uid, service_uid);
  EXPECT_EQ(st.st_gid, service_uid);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
}

TEST_F(KeyFileTest, ReadableByOthersIsRefusedWithTheFix) {
  ASSERT_TRUE(sa::save_key_file(path_, sa::new_keyring()).ok());
  for (mode_t mode : {0644, 0640, 0604, 0660}) {
    ::chmod(path_.c_str(), mode);
    auto loaded = sa::load_key_file(path_);
    ASSERT_FALSE(loaded) << std::oct << mode;
    EXPECT_NE(loaded.error().find("accessible by others"), std::string::npos) << loaded.error();
    EXPECT_NE(loaded.error().find("chmod 600 " + path_), std::string::npos) << loaded.error();
  }
  ::chmod(path_.c_str(), 0400);  // read-only for the owner is fine
  EXPECT_TRUE(sa::load_key_file(path_));
}

TEST_F(KeyFileTest, MalformedFilesNameLineAndProblem) {
  const std::string key(64, 'a');
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {
      {"", "is empty"},
      {"stereoball-keys 2\n", "line 1: expected 'stereoball-keys 1'"},
      {"stereoball-keys 1\nkey 1 sign abc\n", "line 2: key must be 64 hex digits"},
      {"stereoball-keys 1\nkey 1 owns " + key + "\n", "unknown role 'owns'"},
      {"stereoball-keys 1\nkey 1 sign " + key + " extra\n", "unexpected 'extra'"},
      {"stereoball-keys 1\nkey 1 staged " + key + "\n", "exactly one signing key"},
      {"stereoball-keys 1\nkey 1 sign " + key + "\nkey 1 staged " + key + "\n", "twice"},
      {"stereoball-keys 1\nlock 1\n", "expected 'key ...'"},
  };
  for (const auto& c : cases) {
    write_raw(c.text, 0600);
    auto loaded = sa::load_key_file(path_);
    ASSERT_FALSE(loaded) << c.text;
    EXPECT_NE(loaded.error().find(c.expected), std::string::npos) << loaded.error();
    EXPECT_NE(loaded.error().find(path_), std::string::npos) << loaded.error();
  }
  fs::remove(path_);
  EXPECT_NE(sa::load_key_file(path_).error().find("not found"), std::string::npos);
}

TEST(KeyRotation, OldKeyKeepsAGracePeriodAndANewOneSigns) {
  const sa::Keyring first = sa::new_keyring();
  const sa::Keyring second = sa::rotate(first, kNowNs, 60 * kSecondNs);
  ASSERT_TRUE(second.validate().ok());
  ASSERT_EQ(second.keys.size(), 2u);
  EXPECT_EQ(second.signing()->id, 2u);
  EXPECT_NE(second.signing()->key, first.keys[0].key);
  EXPECT_NE(second.accepted(1, kNowNs + 60 * kSecondNs - 1), nullptr);
  EXPECT_EQ(second.accepted(1, kNowNs + 60 * kSecondNs), nullptr);
  // A later rotation drops the key whose grace is over
  const sa::Keyring third = sa::rotate(second, kNowNs + 61 * kSecondNs, 60 * kSecondNs);
  ASSERT_EQ(third.keys.size(), 2u);
  EXPECT_EQ(third.accepted(1, kNowNs + 61 * kSecondNs), nullptr);
  EXPECT_EQ(third.signing()->id, 3u);
}

TEST(KeyRotation, StagedKeyIsAcceptedFirstAndSignsAfterRotate) {
  const sa::Keyring ring = sa::stage(sa::new_keyring());
  ASSERT_TRUE(ring.validate().ok());
  EXPECT_EQ(ring.signing()->id, 1u);
  EXPECT_NE(ring.accepted(2, kNowNs), nullptr);  // hosts with this file accept the next key
  const sa::Keyring rotated = sa::rotate(ring, kNowNs, 60 * kSecondNs);
  EXPECT_EQ(rotated.signing()->id, 2u);
  EXPECT_EQ(rotated.signing()->key, ring.keys[1].key);
  EXPECT_NE(rotated.accepted(1, kNowNs), nullptr);
}
