#pragma once
// Topic<T>: a topic of the table, created in a participant.

#include <type_traits>

#include "common/dds/auth_session.hpp"
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
      : spec_(def.spec), topic_(create_topic(participant, def.spec)) {
    // The table and the message must agree on which topics carry an AuthTag.
    if (Authenticated<T> != (def.spec.auth != topics::Auth::kNone)) {
      throw Error("topic " + std::string(def.spec.name) + ": AuthTag and topic table disagree",
                  DDS_RETCODE_BAD_PARAMETER);
    }
  }
  EntityHandle handle() const { return topic_.handle(); }
  const topics::TopicSpec& spec() const { return spec_; }

 private:
  topics::TopicSpec spec_;
  Entity topic_;
};

}  // namespace stereoball::dds
