#pragma once
// Topic<T>: a topic of the table, created in a participant.

#include "common/dds/entity.hpp"
#include "common/dds/error.hpp"
#include "common/dds/participant.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::dds {

/// Creates the untyped topic for spec in participant.
Entity create_topic(const DomainParticipant& participant, const topics::TopicSpec& spec);

template <typename T>
class Topic {
 public:
  Topic(const DomainParticipant& participant, const topics::Topic<T>& def)
      : spec_(def.spec), topic_(create_topic(participant, def.spec)) {}
  EntityHandle handle() const { return topic_.handle(); }
  const topics::TopicSpec& spec() const { return spec_; }

 private:
  topics::TopicSpec spec_;
  Entity topic_;
};

}  // namespace stereoball::dds
