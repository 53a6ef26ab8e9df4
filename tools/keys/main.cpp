// stereoball keys init|show|rotate: makes, shows and rotates the deployment key file that
// authenticates every control and configuration sample (components/common/auth).

#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/auth/key_file.hpp"
#include "common/util/deployment.hpp"

namespace {

namespace sa = stereoball::auth;

int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int fail(const std::string& message) {
  std::fprintf(stderr, "stereoball keys: %s\n", message.c_str());
  return 2;
}

int init(const std::string& path, bool force) {
  if (std::filesystem::exists(path) && !force) {
    return fail(path +
                " exists (its keys may be in use; 'keys rotate' replaces them safely, "
                "--force overwrites)");
  }
  if (auto e = sa::save_key_file(path, sa::new_keyring()); !e) return fail(e.error());
  std::printf(
      "created %s (mode 0600) with signing key 1.\n"
      "Copy it, mode 0600, to every host of this deployment and set "
      "STEREOBALL_KEY_FILE=%s (or --key-file) for every node and tool.\n",
      path.c_str(), path.c_str());
  return 0;
}

int show(const std::string& path) {
  auto ring = sa::load_key_file(path);
  if (!ring) return fail(ring.error());
  std::printf("%s\n%s", path.c_str(), sa::describe(*ring, now_ns()).c_str());
  return 0;
}

int rotate(const std::string& path, bool staged, double grace_s) {
  auto ring = sa::load_key_file(path);
  if (!ring) return fail(ring.error());
  const sa::Keyring next =
      staged ? sa::stage(*ring) : sa::rotate(*ring, now_ns(), static_cast<int64_t>(grace_s * 1e9));
  if (auto e = sa::save_key_file(path, next); !e) return fail(e.error());
  std::printf("%s\n%s", path.c_str(), sa::describe(next, now_ns()).c_str());
  std::printf(staged ? "Copy the file to every host, then run 'stereoball keys rotate' and copy "
                       "it again.\n"
                     : "Running nodes pick the new keys up within a second; copy the file to "
                       "the other hosts within the grace period.\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball keys: the deployment key file. Every sample of cmd/velocity, cmd/estop,\n"
      "ball/track, ball/detection and stereo/calibration carries a MAC made with it; readers\n"
      "drop samples without a valid one. Without a key file nodes run on loopback only."};
  app.require_subcommand(1);
  app.fallthrough();  // the shared options may follow the subcommand
  // On a host with a systemd role, its settings file names the key file.
  stereoball::deployment::import_env_file();
  const char* env = std::getenv("STEREOBALL_KEY_FILE");
  std::string path = env ? env : "";
  app.add_option("-f,--file", path,
                 "key file (default: $STEREOBALL_KEY_FILE, also from "
                 "/etc/stereoball/stereoball.env)");
  bool force = false;
  auto* init_cmd = app.add_subcommand("init", "create a key file with a new random key");
  init_cmd->add_flag("--force", force, "overwrite an existing file");
  app.add_subcommand("show", "list the keys (ids, roles, fingerprints; never the key)");
  bool staged = false;
  double grace_s = 600;
  auto* rotate_cmd = app.add_subcommand(
      "rotate", "a new key signs (or the staged one); the old one is accepted for --grace s");
  rotate_cmd->add_flag("--stage", staged,
                       "only add the next key, accepted but not signing (multi-host: copy "
                       "everywhere first, then rotate)");
  rotate_cmd->add_option("--grace", grace_s, "seconds the old key stays accepted")
      ->check(CLI::Range(1.0, 7.0 * 86400))
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  if (path.empty()) return fail("no key file: pass --file or set STEREOBALL_KEY_FILE");
  if (init_cmd->parsed()) return init(path, force);
  if (rotate_cmd->parsed()) return rotate(path, staged, grace_s);
  return show(path);
}
