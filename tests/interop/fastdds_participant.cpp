#include "fastdds_participant.hpp"

#include <fastdds/rtps/transport/UDPv4TransportDescriptor.h>
#include <fastrtps/utils/IPLocator.h>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/qos/DomainParticipantQos.hpp>

#include <memory>

namespace stereoball::interop {

namespace fdds = eprosima::fastdds::dds;

fdds::DomainParticipant* make_loopback_participant(int domain_id) {
  fdds::DomainParticipantQos qos;
  qos.name("stereoball_interop_fastdds");
  auto udp = std::make_shared<eprosima::fastdds::rtps::UDPv4TransportDescriptor>();
  udp->interfaceWhiteList.emplace_back("127.0.0.1");
  // Stereo frames are ~1.8 MB raw: the same socket buffers as config/cyclonedds/loopback.xml.
  udp->sendBufferSize = 4 * 1024 * 1024;
  udp->receiveBufferSize = 16 * 1024 * 1024;
  udp->maxMessageSize = 65500;
  // Cyclone's loopback configuration allows participant indices up to 60.
  udp->maxInitialPeersRange = 61;
  qos.transport().use_builtin_transports = false;
  qos.transport().user_transports.push_back(udp);

  eprosima::fastrtps::rtps::Locator_t peer;
  peer.kind = LOCATOR_KIND_UDPv4;
  eprosima::fastrtps::rtps::IPLocator::setIPv4(peer, 127, 0, 0, 1);
  qos.wire_protocol().builtin.initialPeersList.push_back(peer);
  qos.wire_protocol().builtin.avoid_builtin_multicast = true;
  return fdds::DomainParticipantFactory::get_instance()->create_participant(domain_id, qos);
}

}  // namespace stereoball::interop
