// stereoball estop engage|release|status: the operator's emergency stop. engage and release
// publish an authenticated cmd/estop sample (the deployment key signs it); every node that
// obeys the stop (the base, the motion controller) holds the newest one and re-publishes it,
// so it outlives this program and the restart of any node. release needs a deliberate action:
// --confirm, or RELEASE typed at a terminal.

#include <unistd.h>
#include "common/util/cli11.hpp"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <string>
#include <thread>

#include "common/dds/reader.hpp"
#include "common/dds/writer.hpp"
#include "common/node/common_flags.hpp"
#include "common/node/node_runner.hpp"

namespace {

namespace sb = stereoball;
using Estop = stereoball_msg_EmergencyStop;

int fail(const std::string& message, int code = 2) {
  std::fprintf(stderr, "stereoball estop: %s\n", message.c_str());
  return code;
}

std::string who() {
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  const char* user = std::getenv("USER");
  return std::string(user ? user : "operator") + "@" + host;
}

// The operator typed RELEASE (only asked at a terminal).
bool confirmed_at_terminal() {
  if (!isatty(STDIN_FILENO)) return false;
  std::fprintf(stderr, "Type RELEASE to let the robot move again: ");
  std::string line;
  std::getline(std::cin, line);
  return line == "RELEASE";
}

int publish(const sb::node::CommonOptions& common, bool engaged, const std::string& reason,
            double wait_s) {
  sb::dds::DomainParticipant participant({common.domain_id, common.partition, common.key_file});
  sb::dds::DataWriter<Estop> writer(participant, sb::topics::kEmergencyStop);
  const auto wait_ns = static_cast<int64_t>(wait_s * 1e9);
  // Transient-local: a holder that matches later still gets the stop; the pause only lets
  // discovery finish so the count printed below is complete.
  if (writer.wait_for_readers(1, wait_ns))
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::string text = reason + " (" + who() + ")";
  Estop msg{};
  msg.stamp_ns = sb::node::now_ns();
  msg.engaged = engaged;
  msg.reason = text.data();
  writer.write(msg);
  const bool acked = writer.wait_for_acks(wait_ns);
  const uint32_t readers = writer.matched_readers();
  std::printf("emergency stop %s: %s; delivered to %u reader%s%s\n",
              engaged ? "ENGAGED" : "released", text.c_str(), readers, readers == 1 ? "" : "s",
              acked ? "" : " (not all acknowledged)");
  if (!participant.auth().keyed()) {
    std::printf("warning: unauthenticated (no deployment key): loopback only\n");
  }
  if (readers == 0) {
    std::string dds = "Cyclone's defaults";
    if (const char* uri = std::getenv("CYCLONEDDS_URI")) dds = uri;
    if (!participant.auth().keyed()) dds = "built into keyless processes (loopback only)";
    return fail("no node obeys the stop on domain " + std::to_string(common.domain_id) +
                    (common.partition.empty() ? "" : ", partition " + common.partition) +
                    " right now: nothing holds it (this tool used the DDS configuration " + dds +
                    "; the nodes must use the same: see `stereoball launch`'s log)",
                3);
  }
  return 0;
}

int status(const sb::node::CommonOptions& common, double wait_s) {
  sb::dds::DomainParticipant participant({common.domain_id, common.partition, common.key_file});
  sb::dds::DataReader<Estop> reader(participant, sb::topics::kEmergencyStop);
  reader.wait_for_writers(1, static_cast<int64_t>(wait_s * 1e9));
  // Latched states of every holder arrive right after matching; give them a moment.
  std::optional<sb::dds::Owned<Estop>> newest;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(500);
  while (std::chrono::steady_clock::now() < until) {
    for (auto& s : reader.take()) newest = std::move(s);  // only newer states are delivered
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const uint32_t holders = reader.matched_writers();
  if (!newest) {
    std::printf("state: released (no stop published since the %u holder%s started)\n", holders,
                holders == 1 ? "" : "s");
    return 0;
  }
  const double age_s = (sb::node::now_ns() - (*newest)->auth.stamp_ns) * 1e-9;
  std::printf("state: %s\nreason: %s\nsince: %.1f s ago\nholders: %u\n",
              (*newest)->engaged ? "ENGAGED" : "released",
              (*newest)->reason ? (*newest)->reason : "", age_s, holders);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "stereoball estop: engage or release the emergency stop, or show it. The base and the\n"
      "motion controller obey it themselves and hold it across restarts of any node."};
  app.require_subcommand(1);
  app.fallthrough();  // the shared options may follow the subcommand
  sb::node::CommonOptions common;
  sb::node::add_common_flags(app, common, "", false);
  double wait_s = 5.0;
  app.add_option("--wait", wait_s, "seconds to wait for the nodes that obey the stop")
      ->check(CLI::Range(0.1, 60.0))
      ->capture_default_str();
  std::string reason = "operator";
  auto* engage = app.add_subcommand("engage", "stop the robot (latched)");
  engage->add_option("--reason", reason, "why (logged by every node)");
  bool confirm = false;
  auto* release = app.add_subcommand("release", "let the robot move again (needs confirmation)");
  release->add_option("--reason", reason, "why (logged by every node)");
  release->add_flag("--confirm", confirm, "confirm without a prompt (scripts)");
  app.add_subcommand("status", "show the newest stop state and how many nodes hold it");
  CLI11_PARSE(app, argc, argv);
  try {
    if (engage->parsed()) return publish(common, true, reason, wait_s);
    if (release->parsed()) {
      if (!confirm && !confirmed_at_terminal()) {
        return fail(isatty(STDIN_FILENO)
                        ? "not released (confirmation not typed)"
                        : "release needs --confirm (or RELEASE typed at a terminal)");
      }
      return publish(common, false, reason, wait_s);
    }
    return status(common, wait_s);
  } catch (const std::exception& e) {
    return fail(e.what(), 1);
  }
}
