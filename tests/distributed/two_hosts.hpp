#pragma once
// Two "hosts" on one machine: two network namespaces joined by a veth pair with private
// addresses unique to this run. Needs root and iproute2; everything it creates (namespaces,
// the link, every process left inside them) is removed by the destructor.

#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::distributed {

/// One side of the pair: namespace, interface inside it, its address and the peer's.
struct Host {
  std::string netns;         ///< network namespace name, e.g. "sbrobot12345"
  std::string iface;         ///< veth end inside netns
  std::string address;       ///< IPv4 address of iface (no prefix length)
  std::string peer_address;  ///< address of the other host
};

/// RAII pair of namespaces (robot, workstation) joined by a veth link.
class TwoHosts {
 public:
  TwoHosts();
  ~TwoHosts();
  TwoHosts(const TwoHosts&) = delete;
  TwoHosts& operator=(const TwoHosts&) = delete;

  /// Creates the namespaces and the link; an error (the reason, for GTEST_SKIP) if impossible.
  Status setup();
  /// Adds a third namespace, "rogue", with its own veth link to the robot namespace (another
  /// subnet; the robot's Cyclone interface and peer list do not name it). After setup().
  Status add_rogue();
  const Host& robot() const { return robot_; }
  const Host& workstation() const { return workstation_; }
  const Host& rogue() const { return rogue_; }
  /// Deployment key file every command() passes as STEREOBALL_KEY_FILE ("" = none).
  void set_key_file(const std::string& path) { key_file_ = path; }

  /// argv that runs program in host's namespace with the LAN Cyclone configuration:
  /// ip netns exec NS env -u CYCLONEDDS_URI STEREOBALL_IFACE=.. STEREOBALL_PEER=..
  /// [STEREOBALL_KEY_FILE=..] [extra] argv...
  /// (CYCLONEDDS_URI is removed so the launcher's profile choice, or cyclonedds_uri, applies).
  std::vector<std::string> command(const Host& host, const std::vector<std::string>& argv,
                                   const std::string& cyclonedds_uri = "") const;

  /// `ip link set <robot iface> up|down`; error text on failure.
  Status set_robot_link(bool up) const;
  /// Adds a netem qdisc (delay, loss) on both ends; error text (e.g. no sch_netem) on failure.
  Status add_netem(int delay_ms, double loss_percent) const;
  /// Removes the netem qdiscs (ignores errors).
  void remove_netem() const;

  /// Process ids currently inside host's namespace (`ip netns pids`).
  std::vector<int> pids(const Host& host) const;

 private:
  Status ip(const std::vector<std::string>& args) const;
  void kill_all(const Host& host) const;
  void remove_abandoned() const;

  std::string ip_path_;
  Host robot_, workstation_, rogue_, robot_rogue_side_;
  std::string key_file_;
  bool robot_created_ = false;
  bool workstation_created_ = false;
  bool rogue_created_ = false;
};

/// Path of the `ip` program (iproute2), or "" if none is installed.
std::string find_ip_program();

/// Whether a netem qdisc can be added here (tried on a scratch pair of namespaces); the
/// reason when not (no namespaces, no tc, no sch_netem in the kernel).
Status netem_available();

}  // namespace stereoball::distributed
