#pragma once
// DataWriter<T>: typed writer for a topic of the table.

#include <dds/dds.h>

#include <cstdint>

#include "common/dds/entity.hpp"
#include "common/dds/topic.hpp"

namespace stereoball::dds {

/// Creates an untyped writer for topic_handle with spec's QoS in participant's publisher.
Entity create_writer(const DomainParticipant& participant, EntityHandle topic_handle,
                     const topics::QosSpec& qos);
/// Number of readers currently matched with writer.
uint32_t matched_readers(EntityHandle writer);
/// Blocks until at least n readers are matched or timeout_ns passes; true if matched.
bool wait_for_readers(EntityHandle writer, uint32_t n, int64_t timeout_ns);

template <typename T>
class DataWriter {
 public:
  DataWriter(const DomainParticipant& participant, const topics::Topic<T>& def)
      : DataWriter(participant, def, def.spec.qos) {}
  /// With a QoS other than the table's (tools and benchmarks only).
  DataWriter(const DomainParticipant& participant, const topics::Topic<T>& def,
             const topics::QosSpec& qos)
      : topic_(participant, def),
        writer_(create_writer(participant, topic_.handle(), qos)),
        auth_(&participant.auth()),
        link_(auth::random_link_id()) {}

  /// Publishes sample, stamped now; authenticated topics are signed on the way (the caller's
  /// tag is ignored). Throws dds::Error on failure.
  void write(const T& sample) {
    if constexpr (Authenticated<T>) {
      const T copy = signed_copy(sample);
      check(dds_write(writer_.handle(), &copy), "dds_write");
    } else {
      check(dds_write(writer_.handle(), &sample), "dds_write");
    }
  }
  /// Publishes sample with an explicit source timestamp (ns since epoch).
  void write(const T& sample, int64_t source_stamp_ns) {
    if constexpr (Authenticated<T>) {
      const T copy = signed_copy(sample);
      check(dds_write_ts(writer_.handle(), &copy, source_stamp_ns), "dds_write_ts");
    } else {
      check(dds_write_ts(writer_.handle(), &sample, source_stamp_ns), "dds_write_ts");
    }
  }
  /// Publishes a sample that already carries its signer's tag, unchanged (a relay of a
  /// latched state keeps the operator's authenticated stamp).
  void forward(const T& sample) requires Authenticated<T> {
    check(dds_write(writer_.handle(), &sample), "dds_write");
  }
  /// The copy of sample that write() would send: tag filled (link, stamp, key id, MAC). With
  /// forward() the same signed sample can be sent more than once (tests of the wire format).
  T signed_copy(const T& sample) requires Authenticated<T> {
    T copy = sample;  // shallow: strings and sequences still point at the caller's buffers
    auth_->sign(topic_.spec(), link_, copy.auth, &copy);
    return copy;
  }
  /// Blocks until every matched reader acknowledged what was written, or timeout_ns.
  bool wait_for_acks(int64_t timeout_ns) const {
    return dds_wait_for_acks(writer_.handle(), timeout_ns) == DDS_RETCODE_OK;
  }
  uint32_t matched_readers() const { return dds::matched_readers(writer_.handle()); }
  bool wait_for_readers(uint32_t n, int64_t timeout_ns) const {
    return dds::wait_for_readers(writer_.handle(), n, timeout_ns);
  }
  EntityHandle handle() const { return writer_.handle(); }
  const topics::TopicSpec& spec() const { return topic_.spec(); }

 private:
  Topic<T> topic_;
  Entity writer_;
  AuthSession* auth_;
  auth::LinkClock link_;
};

}  // namespace stereoball::dds
