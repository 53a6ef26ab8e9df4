#pragma once
// Stereo frames robot -> workstation across the veth link: sb_frame_publisher in the robot
// namespace, an observer in the workstation namespace, both with a deployment key (a keyless
// process is confined to loopback and nothing would cross). Used by the distributed benchmark.

#include <string>
#include <vector>

#include "common/util/result.hpp"
#include "observer_log.hpp"
#include "two_hosts.hpp"

namespace stereoball::distributed {

/// What one run publishes and how the receiving side is configured.
struct FrameTransportOptions {
  std::string encoding = "bgr8";  ///< sb_frame_publisher --encoding (bgr8, jpeg, png)
  int quality = 90;               ///< JPEG quality
  double rate_hz = 30;            ///< publishing rate
  double duration_s = 10;         ///< publishing time
  int domain = 0;
  std::string partition;     ///< "" = one made from this process id
  std::string receiver_uri;  ///< the observer's CYCLONEDDS_URI; "" = config/cyclonedds/lan.xml
};

/// What crossed the link.
struct FrameTransport {
  long sent = 0;                  ///< frames the publisher says it sent
  std::vector<FrameRx> received;  ///< frames the observer received, in order
};

/// Runs one transport between hosts (already set up) with a fresh deployment key; an error names
/// the step that failed (key, observer, publisher) with its output.
Result<FrameTransport> run_frame_transport(TwoHosts& hosts, const FrameTransportOptions& options);

}  // namespace stereoball::distributed
