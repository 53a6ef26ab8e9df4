#pragma once
// QoS objects built from the topic table's QosSpec.

#include <dds/dds.h>

#include <memory>
#include <string>

#include "common/dds/entity.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::dds {

/// Owned dds_qos_t.
class Qos {
 public:
  Qos();
  ~Qos();
  Qos(Qos&&) noexcept;
  Qos& operator=(Qos&&) noexcept;
  Qos(const Qos&) = delete;
  Qos& operator=(const Qos&) = delete;
  dds_qos_t* get() const { return qos_; }

  /// Reader/writer QoS for a topic of the table.
  static Qos for_topic(const topics::QosSpec& spec);
  /// Publisher/subscriber QoS with one partition ("" = default partition).
  static Qos for_partition(const std::string& partition);

 private:
  dds_qos_t* qos_;
};

/// The QoS an existing reader or writer actually has (reliability, durability, history, deadline).
topics::QosSpec actual_qos(EntityHandle reader_or_writer);

}  // namespace stereoball::dds
