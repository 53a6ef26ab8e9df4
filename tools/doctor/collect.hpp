#pragma once
// The DDS side of `stereoball doctor`: joins the deployment's domain and partition, listens
// for a bounded time and fills Observations (heartbeats, frames, calibration, e-stop, a few
// live pairs measured after rectification).

#include <string>
#include <vector>

#include "common/node/common_flags.hpp"
#include "doctor_checks.hpp"

namespace stereoball::doctor {

struct CollectOptions {
  node::CommonOptions common;    ///< domain, partition, key file
  double listen_s = 4.0;         ///< how long to listen
  int pairs = 3;                 ///< live pairs kept for the image measures
  bool probe_partitions = true;  ///< when nothing answers, listen once more in every partition
};

/// Listens and returns what it heard (expected_nodes, camera_config are the caller's).
/// Throws dds::Error / std::runtime_error when DDS or the key file cannot be used.
Observations collect(const CollectOptions& options);

}  // namespace stereoball::doctor
