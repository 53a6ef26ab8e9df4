#pragma once
// Serialized (CDR) access to any topic of the table: the recorder takes samples
// exactly as they travelled and the player writes them back, without decoding.

#include <cstdint>
#include <span>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/participant.hpp"
#include "stereoball/topics.hpp"

struct ddsi_sertype;

namespace stereoball::dds {

/// One sample as it travelled: CDR bytes including the 4-byte encapsulation header.
struct SerializedSample {
  std::vector<uint8_t> cdr;
  int64_t source_stamp_ns = 0;  ///< writer's source timestamp, ns since epoch
};

class SerializedReader {
 public:
  SerializedReader(const DomainParticipant& participant, const topics::TopicSpec& spec);
  SerializedReader(const DomainParticipant& participant, const topics::TopicSpec& spec,
                   const topics::QosSpec& qos);
  /// Appends up to max samples with valid data to out; returns how many.
  size_t take(std::vector<SerializedSample>& out, size_t max = 64);
  EntityHandle handle() const { return reader_.handle(); }
  const topics::TopicSpec& spec() const { return spec_; }

 private:
  topics::TopicSpec spec_;
  Entity topic_;
  Entity reader_;
};

class SerializedWriter {
 public:
  SerializedWriter(const DomainParticipant& participant, const topics::TopicSpec& spec);
  ~SerializedWriter();
  SerializedWriter(const SerializedWriter&) = delete;
  SerializedWriter& operator=(const SerializedWriter&) = delete;
  /// Publishes cdr (with encapsulation header) unchanged. Throws dds::Error on failure.
  void write(std::span<const uint8_t> cdr);
  bool wait_for_readers(uint32_t n, int64_t timeout_ns) const;
  EntityHandle handle() const { return writer_.handle(); }
  const topics::TopicSpec& spec() const { return spec_; }

 private:
  topics::TopicSpec spec_;
  Entity topic_;
  Entity writer_;
  const ddsi_sertype* sertype_ = nullptr;
};

}  // namespace stereoball::dds
