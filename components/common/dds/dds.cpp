// The one place that talks to the Cyclone DDS C API (with the templates in the headers).
#include <dds/dds.h>
#include <dds/ddsi/ddsi_serdata.h>
#include <dds/ddsi/ddsi_sertype.h>

#include <unistd.h>
#include <chrono>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "common/dds/auth_session.hpp"
#include "common/dds/error.hpp"
#include "common/dds/participant.hpp"
#include "common/dds/qos.hpp"
#include "common/dds/reader.hpp"
#include "common/dds/serialized.hpp"
#include "common/dds/shared_memory.hpp"
#include "common/dds/topic.hpp"
#include "common/dds/waitset.hpp"
#include "common/dds/writer.hpp"
#include "common/util/deployment.hpp"
#include "common/util/log.hpp"

namespace stereoball::dds {

// ---- errors and entities ----------------------------------------------------------------

Error::Error(const std::string& operation, int return_code)
    : std::runtime_error(operation + " failed: " + dds_strretcode(return_code)),
      code_(return_code) {}

int check(int rc, const char* operation) {
  if (rc < 0) throw Error(operation, rc);
  return rc;
}

void Entity::reset() {
  if (handle_ > 0) dds_delete(handle_);
  handle_ = 0;
}

// ---- QoS ---------------------------------------------------------------------------------

Qos::Qos() : qos_(dds_create_qos()) {}
Qos::~Qos() {
  if (qos_) dds_delete_qos(qos_);
}
Qos::Qos(Qos&& other) noexcept : qos_(std::exchange(other.qos_, nullptr)) {}
Qos& Qos::operator=(Qos&& other) noexcept {
  if (this != &other) {
    if (qos_) dds_delete_qos(qos_);
    qos_ = std::exchange(other.qos_, nullptr);
  }
  return *this;
}

Qos Qos::for_topic(const topics::QosSpec& spec) {
  Qos qos;
  if (spec.reliability == topics::Reliability::kReliable) {
    dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  } else {
    dds_qset_reliability(qos.get(), DDS_RELIABILITY_BEST_EFFORT, 0);
  }
  dds_qset_durability(qos.get(), spec.durability == topics::Durability::kTransientLocal
                                     ? DDS_DURABILITY_TRANSIENT_LOCAL
                                     : DDS_DURABILITY_VOLATILE);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, spec.history_depth);
  if (spec.deadline_ns > 0) dds_qset_deadline(qos.get(), spec.deadline_ns);
  return qos;
}

Qos Qos::for_partition(const std::string& partition) {
  Qos qos;
  if (!partition.empty()) dds_qset_partition1(qos.get(), partition.c_str());
  return qos;
}

topics::QosSpec actual_qos(EntityHandle entity) {
  Qos qos;
  check(dds_get_qos(entity, qos.get()), "dds_get_qos");
  topics::QosSpec spec;
  dds_reliability_kind_t reliability{};
  dds_duration_t blocking = 0;
  if (dds_qget_reliability(qos.get(), &reliability, &blocking)) {
    spec.reliability = reliability == DDS_RELIABILITY_RELIABLE ? topics::Reliability::kReliable
                                                               : topics::Reliability::kBestEffort;
  }
  dds_durability_kind_t durability{};
  if (dds_qget_durability(qos.get(), &durability)) {
    spec.durability = durability == DDS_DURABILITY_TRANSIENT_LOCAL
                          ? topics::Durability::kTransientLocal
                          : topics::Durability::kVolatile;
  }
  dds_history_kind_t history{};
  int32_t depth = 0;
  if (dds_qget_history(qos.get(), &history, &depth)) {
    spec.history_depth = history == DDS_HISTORY_KEEP_ALL ? -1 : depth;
  }
  dds_duration_t deadline = DDS_INFINITY;
  if (dds_qget_deadline(qos.get(), &deadline))
    spec.deadline_ns = deadline == DDS_INFINITY ? 0 : deadline;
  return spec;
}

// ---- participant and topics --------------------------------------------------------------

namespace {

// Keyless processes get this configuration whatever CYCLONEDDS_URI says: nothing they send or
// accept can leave or enter the host (same settings as config/cyclonedds/loopback.xml).
constexpr const char* kLoopbackOnlyXml =
    "<CycloneDDS><Domain Id=\"any\"><General><Interfaces>"
    "<NetworkInterface name=\"lo\" multicast=\"false\"/></Interfaces>"
    "<AllowMulticast>false</AllowMulticast><MaxMessageSize>65500B</MaxMessageSize></General>"
    "<Discovery><ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>60</MaxAutoParticipantIndex>"
    "<Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
    "<Internal><SocketReceiveBufferSize min=\"default\" max=\"16MB\"/>"
    "<SocketSendBufferSize min=\"default\" max=\"4MB\"/></Internal></Domain></CycloneDDS>";

// An explicitly created domain lives until deleted, so the keyless participants of a process
// share one per domain id and the last to go deletes it.
std::shared_ptr<Entity> loopback_only_domain(int domain_id) {
  static std::mutex mutex;
  static std::map<int, std::weak_ptr<Entity>> domains;
  std::lock_guard lock(mutex);
  if (auto domain = domains[domain_id].lock()) return domain;
  const dds_entity_t handle = dds_create_domain(domain_id, kLoopbackOnlyXml);
  if (handle == DDS_RETCODE_PRECONDITION_NOT_MET) {
    throw Error("domain " + std::to_string(domain_id) +
                    " already runs in this process with a deployment key; a keyless "
                    "participant cannot join it",
                handle);
  }
  auto domain = std::make_shared<Entity>(check(handle, "dds_create_domain(loopback only)"));
  domains[domain_id] = domain;
  return domain;
}

void warn_keyless_once() {
  static std::once_flag once;
  std::call_once(once, [] {
    log::warn(
        "UNAUTHENTICATED: no deployment key (set STEREOBALL_KEY_FILE or --key-file; "
        "'stereoball keys init' makes one). Confined to the loopback interface: anything on "
        "this host can command the robot.");
  });
}

}  // namespace

std::string resolve_key_file(const std::optional<std::string>& key_file) {
  if (key_file) return *key_file;
  const char* env = std::getenv("STEREOBALL_KEY_FILE");
  return env ? env : "";
}

DomainParticipant::DomainParticipant(const ParticipantOptions& options) : options_(options) {
  if (options.domain_id < 0 || options.domain_id > 232) {
    throw Error("domain id " + std::to_string(options.domain_id) + " (allowed 0..232)",
                DDS_RETCODE_BAD_PARAMETER);
  }
  // The roles' settings file may name the key file (a tool run by hand on a robot).
  deployment::import_env_file();
  // Throws std::runtime_error naming the key file and its problem (mode, syntax...).
  auth_ = std::make_shared<AuthSession>(resolve_key_file(options.key_file));
  if (auth_->keyed()) {
    // Before Cyclone reads its configuration: the deployment's, so that a tool reaches the
    // nodes of a profile or a systemd role without being told which file they use.
    if (const auto& config = deployment::use_deployment_dds_config(); !config) {
      throw std::runtime_error(config.error() + " (or set CYCLONEDDS_URI)");
    }
  }
  // Before Cyclone reads its configuration: never wait for a RouDi daemon that is not there.
  ensure_shared_memory_usable();
  if (!auth_->keyed()) {
    warn_keyless_once();
    loopback_domain_ = loopback_only_domain(options.domain_id);
  }
  participant_ = Entity(check(
      dds_create_participant(static_cast<dds_domainid_t>(options.domain_id), nullptr, nullptr),
      "dds_create_participant"));
  const Qos qos = Qos::for_partition(options.partition);
  publisher_ = Entity(check(dds_create_publisher(participant_.handle(), qos.get(), nullptr),
                            "dds_create_publisher"));
  subscriber_ = Entity(check(dds_create_subscriber(participant_.handle(), qos.get(), nullptr),
                             "dds_create_subscriber"));
}

std::string DomainParticipant::built_in_config() const {
  return loopback_domain_ ? kLoopbackOnlyXml : "";
}

const char* keyless_cyclone_config() {
  return kLoopbackOnlyXml;
}

int domain_from_env(int fallback) {
  const char* text = std::getenv("STEREOBALL_DOMAIN");
  if (!text || !*text) return fallback;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value < 0 || value > 232) return fallback;
  return static_cast<int>(value);
}

Entity create_topic(const DomainParticipant& participant, const topics::TopicSpec& spec) {
  const std::string name(spec.name);
  return Entity(
      check(dds_create_topic(participant.handle(), spec.descriptor, name.c_str(), nullptr, nullptr),
            ("dds_create_topic(" + name + ")").c_str()));
}

// ---- writers and readers -----------------------------------------------------------------

Entity create_writer(const DomainParticipant& participant, EntityHandle topic_handle,
                     const topics::QosSpec& qos_spec) {
  const Qos qos = Qos::for_topic(qos_spec);
  return Entity(check(dds_create_writer(participant.publisher(), topic_handle, qos.get(), nullptr),
                      "dds_create_writer"));
}

Entity create_reader(const DomainParticipant& participant, EntityHandle topic_handle,
                     const topics::QosSpec& qos_spec) {
  const Qos qos = Qos::for_topic(qos_spec);
  return Entity(check(dds_create_reader(participant.subscriber(), topic_handle, qos.get(), nullptr),
                      "dds_create_reader"));
}

uint32_t matched_readers(EntityHandle writer) {
  dds_publication_matched_status_t status{};
  check(dds_get_publication_matched_status(writer, &status), "dds_get_publication_matched_status");
  return status.current_count;
}

uint32_t matched_writers(EntityHandle reader) {
  dds_subscription_matched_status_t status{};
  check(dds_get_subscription_matched_status(reader, &status),
        "dds_get_subscription_matched_status");
  return status.current_count;
}

namespace {
// Polls a predicate with a deadline; discovery has no waitable "n matched" event.
template <typename Pred>
bool poll_until(Pred pred, int64_t timeout_ns) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::nanoseconds(timeout_ns);
  while (!pred()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}
}  // namespace

bool wait_for_readers(EntityHandle writer, uint32_t n, int64_t timeout_ns) {
  return poll_until([&] { return matched_readers(writer) >= n; }, timeout_ns);
}

bool wait_for_writers(EntityHandle reader, uint32_t n, int64_t timeout_ns) {
  return poll_until([&] { return matched_writers(reader) >= n; }, timeout_ns);
}

uint64_t take_lost_count(EntityHandle reader) {
  dds_sample_lost_status_t lost{};
  dds_sample_rejected_status_t rejected{};
  dds_get_sample_lost_status(reader, &lost);
  dds_get_sample_rejected_status(reader, &rejected);
  return static_cast<uint64_t>(lost.total_count_change) +
         static_cast<uint64_t>(rejected.total_count_change);
}

// ---- waitset -----------------------------------------------------------------------------

ReadCondition::ReadCondition(EntityHandle reader)
    : condition_(
          check(dds_create_readcondition(reader, DDS_ANY_STATE), "dds_create_readcondition")) {}

GuardCondition::GuardCondition(const DomainParticipant& participant)
    : condition_(
          check(dds_create_guardcondition(participant.handle()), "dds_create_guardcondition")) {}
void GuardCondition::trigger() {
  dds_set_guardcondition(condition_.handle(), true);
}
void GuardCondition::reset() {
  dds_set_guardcondition(condition_.handle(), false);
}

WaitSet::WaitSet(const DomainParticipant& participant)
    : waitset_(check(dds_create_waitset(participant.handle()), "dds_create_waitset")) {}

void WaitSet::attach(EntityHandle condition, intptr_t token) {
  check(dds_waitset_attach(waitset_.handle(), condition, token), "dds_waitset_attach");
  attached_.push_back(condition);
}

void WaitSet::detach(EntityHandle condition) {
  dds_waitset_detach(waitset_.handle(), condition);
  std::erase(attached_, condition);
}

std::vector<intptr_t> WaitSet::wait(int64_t timeout_ns) {
  std::vector<dds_attach_t> triggered(attached_.size() + 1);
  const int n = check(dds_waitset_wait(waitset_.handle(), triggered.data(), triggered.size(),
                                       timeout_ns < 0 ? 0 : timeout_ns),
                      "dds_waitset_wait");
  return {triggered.begin(), triggered.begin() + n};
}

// ---- serialized samples ------------------------------------------------------------------

SerializedReader::SerializedReader(const DomainParticipant& participant,
                                   const topics::TopicSpec& spec)
    : SerializedReader(participant, spec, spec.qos) {}

SerializedReader::SerializedReader(const DomainParticipant& participant,
                                   const topics::TopicSpec& spec, const topics::QosSpec& qos)
    : spec_(spec),
      topic_(create_topic(participant, spec)),
      reader_(create_reader(participant, topic_.handle(), qos)) {}

size_t SerializedReader::take(std::vector<SerializedSample>& out, size_t max) {
  size_t taken = 0;
  while (taken < max) {
    ddsi_serdata* data = nullptr;
    dds_sample_info_t info;
    const int n =
        check(dds_takecdr(reader_.handle(), &data, 1, &info, DDS_ANY_STATE), "dds_takecdr");
    if (n == 0) break;
    if (info.valid_data) {
      SerializedSample sample;
      sample.cdr.resize(ddsi_serdata_size(data));
      ddsi_serdata_to_ser(data, 0, sample.cdr.size(), sample.cdr.data());
      sample.source_stamp_ns = info.source_timestamp;
      out.push_back(std::move(sample));
      ++taken;
    }
    ddsi_serdata_unref(data);
  }
  return taken;
}

namespace {
// Cyclone 0.10 has no public call returning a topic's sertype, and writecdr needs it. The
// sertype is found by writing one zeroed sample through a private partition of this
// participant to a local reader and taking it as serialized data: its serdata carries the
// topic's sertype. Nothing leaves the process (no remote reader is in that partition).
const ddsi_sertype* probe_sertype(const DomainParticipant& participant, EntityHandle topic,
                                  const topics::TopicSpec& spec) {
  const std::string partition =
      "stereoball.sertype-probe." + std::to_string(getpid()) + "." + std::to_string(topic);
  const Qos group_qos = Qos::for_partition(partition);
  Entity publisher(check(dds_create_publisher(participant.handle(), group_qos.get(), nullptr),
                         "dds_create_publisher(probe)"));
  Entity subscriber(check(dds_create_subscriber(participant.handle(), group_qos.get(), nullptr),
                          "dds_create_subscriber(probe)"));
  topics::QosSpec probe_spec{topics::Reliability::kReliable, topics::Durability::kVolatile, 1, 0};
  const Qos qos = Qos::for_topic(probe_spec);
  Entity reader(check(dds_create_reader(subscriber.handle(), topic, qos.get(), nullptr),
                      "dds_create_reader(probe)"));
  Entity writer(check(dds_create_writer(publisher.handle(), topic, qos.get(), nullptr),
                      "dds_create_writer(probe)"));
  std::vector<unsigned char> zeroed(spec.descriptor->m_size, 0);
  check(dds_write(writer.handle(), zeroed.data()), "dds_write(probe)");
  ddsi_serdata* data = nullptr;
  dds_sample_info_t info;
  for (int attempt = 0; attempt < 200; ++attempt) {
    if (check(dds_takecdr(reader.handle(), &data, 1, &info, DDS_ANY_STATE), "dds_takecdr(probe)") >
        0)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!data) throw Error("sertype probe for " + std::string(spec.name), DDS_RETCODE_TIMEOUT);
  const ddsi_sertype* type = ddsi_sertype_ref(data->type);
  ddsi_serdata_unref(data);
  return type;
}
}  // namespace

SerializedWriter::SerializedWriter(const DomainParticipant& participant,
                                   const topics::TopicSpec& spec)
    : spec_(spec),
      topic_(create_topic(participant, spec)),
      writer_(create_writer(participant, topic_.handle(), spec.qos)),
      sertype_(probe_sertype(participant, topic_.handle(), spec)) {}

SerializedWriter::~SerializedWriter() {
  writer_.reset();
  if (sertype_) ddsi_sertype_unref(const_cast<ddsi_sertype*>(sertype_));
}

void SerializedWriter::write(std::span<const uint8_t> cdr) {
  ddsrt_iovec_t iov;
  iov.iov_base = const_cast<uint8_t*>(cdr.data());
  iov.iov_len = static_cast<decltype(iov.iov_len)>(cdr.size());
  ddsi_serdata* data = ddsi_serdata_from_ser_iov(sertype_, SDK_DATA, 1, &iov, cdr.size());
  if (!data)
    throw Error("decoding recorded CDR for " + std::string(spec_.name), DDS_RETCODE_BAD_PARAMETER);
  check(dds_writecdr(writer_.handle(), data), "dds_writecdr");
}

bool SerializedWriter::wait_for_readers(uint32_t n, int64_t timeout_ns) const {
  return dds::wait_for_readers(writer_.handle(), n, timeout_ns);
}

}  // namespace stereoball::dds
