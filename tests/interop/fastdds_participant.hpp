#pragma once
// A Fast DDS participant set up the way a third-party node joins a StereoBall system on one
// host (deploy/README.md "Third-party DDS nodes"): UDP on the loopback interface only, unicast
// discovery through the initial peer 127.0.0.1 (loopback has no multicast), participant ids
// probed over the same range Cyclone's MaxAutoParticipantIndex allows.

#include <fastdds/dds/domain/DomainParticipant.hpp>

namespace stereoball::interop {

/// A participant in domain_id with the partition applied by the caller's publisher/subscriber.
eprosima::fastdds::dds::DomainParticipant* make_loopback_participant(int domain_id);

}  // namespace stereoball::interop
