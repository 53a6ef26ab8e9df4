#pragma once
// DataReader<T>: typed reader; take() gives owned samples, take_loaned() zero-copy loans.

#include <dds/dds.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <utility>
#include <vector>

#include "common/dds/entity.hpp"
#include "common/dds/topic.hpp"

namespace stereoball::dds {

/// Creates an untyped reader for topic_handle with the given QoS in participant's subscriber.
Entity create_reader(const DomainParticipant& participant, EntityHandle topic_handle,
                     const topics::QosSpec& qos);
/// Number of writers currently matched with reader.
uint32_t matched_writers(EntityHandle reader);
/// Blocks until at least n writers are matched or timeout_ns passes; true if matched.
bool wait_for_writers(EntityHandle reader, uint32_t n, int64_t timeout_ns);
/// Counts of samples lost or rejected by reader since the last call.
uint64_t take_lost_count(EntityHandle reader);

/// A sample owned by the caller; frees its strings and sequences on destruction.
template <typename T>
class Owned {
 public:
  Owned(const dds_topic_descriptor_t* desc) : desc_(desc) {
    std::memset(&value_, 0, sizeof value_);
  }
  ~Owned() { release(); }
  Owned(Owned&& other) noexcept : desc_(other.desc_), source_stamp_ns_(other.source_stamp_ns_) {
    std::memcpy(&value_, &other.value_, sizeof value_);
    std::memset(&other.value_, 0, sizeof other.value_);
  }
  Owned& operator=(Owned&& other) noexcept {
    if (this != &other) {
      release();
      desc_ = other.desc_;
      source_stamp_ns_ = other.source_stamp_ns_;
      std::memcpy(&value_, &other.value_, sizeof value_);
      std::memset(&other.value_, 0, sizeof other.value_);
    }
    return *this;
  }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;

  const T& operator*() const { return value_; }
  const T* operator->() const { return &value_; }
  T* get() { return &value_; }
  /// Source timestamp the writer gave this sample, ns since epoch.
  int64_t source_stamp_ns() const { return source_stamp_ns_; }
  void set_source_stamp_ns(int64_t stamp_ns) { source_stamp_ns_ = stamp_ns; }

 private:
  void release() { dds_sample_free(&value_, desc_, DDS_FREE_CONTENTS); }
  const dds_topic_descriptor_t* desc_;
  T value_;
  int64_t source_stamp_ns_ = 0;
};

/// Samples on loan from the reader; returned to it on destruction. Only valid data is listed.
template <typename T>
class LoanedSamples {
 public:
  static constexpr size_t kMax = 16;
  LoanedSamples(EntityHandle reader, size_t max) : reader_(reader) {
    if (max > kMax) max = kMax;
    buffers_[0] = nullptr;
    const int n = dds_take(reader_, buffers_, infos_, max, static_cast<uint32_t>(max));
    check(n, "dds_take");
    count_ = static_cast<size_t>(n);
  }
  ~LoanedSamples() {
    if (count_ > 0) dds_return_loan(reader_, buffers_, static_cast<int32_t>(count_));
  }
  LoanedSamples(const LoanedSamples&) = delete;
  LoanedSamples& operator=(const LoanedSamples&) = delete;

  size_t size() const { return count_; }
  bool valid(size_t i) const { return infos_[i].valid_data; }
  const T& operator[](size_t i) const { return *static_cast<const T*>(buffers_[i]); }
  const dds_sample_info_t& info(size_t i) const { return infos_[i]; }
  /// Index of the newest valid sample, if any.
  std::optional<size_t> latest_valid() const {
    for (size_t i = count_; i > 0; --i) {
      if (infos_[i - 1].valid_data) return i - 1;
    }
    return std::nullopt;
  }

 private:
  EntityHandle reader_;
  void* buffers_[kMax];
  dds_sample_info_t infos_[kMax];
  size_t count_ = 0;
};

template <typename T>
class DataReader {
 public:
  DataReader(const DomainParticipant& participant, const topics::Topic<T>& def)
      : DataReader(participant, def, def.spec.qos) {}
  /// With a QoS other than the table's (tools only, e.g. a deeper history for `topic hz`).
  DataReader(const DomainParticipant& participant, const topics::Topic<T>& def,
             const topics::QosSpec& qos)
      : desc_(def.spec.descriptor),
        topic_(participant, def),
        reader_(create_reader(participant, topic_.handle(), qos)),
        auth_(&participant.auth()),
        guard_(participant.auth().make_guard(def.spec)) {}

  /// Takes up to max samples with valid data, as owned values (oldest first).
  std::vector<Owned<T>> take(size_t max = 16) {
    std::vector<Owned<T>> out;
    for (;;) {
      Owned<T> sample(desc_);
      void* buffer = sample.get();
      dds_sample_info_t info;
      const int n = check(dds_take(reader_.handle(), &buffer, &info, 1, 1), "dds_take");
      if (n == 0) break;
      // Authenticated topics: forged, replayed or unsigned samples are dropped (and counted).
      if (info.valid_data && authentic(sample)) {
        sample.set_source_stamp_ns(info.source_timestamp);
        out.push_back(std::move(sample));
      }
      if (out.size() >= max) break;
    }
    return out;
  }
  /// Takes everything queued and keeps only the newest valid sample.
  std::optional<Owned<T>> take_latest() {
    auto samples = take(SIZE_MAX);
    if (samples.empty()) return std::nullopt;
    return std::move(samples.back());
  }
  /// Takes up to max samples on loan (zero allocation; give them back by destroying the result).
  LoanedSamples<T> take_loaned(size_t max = LoanedSamples<T>::kMax) requires(
      !Authenticated<T>)  // loans are not checked: authenticated topics use take()
  {
    return LoanedSamples<T>(reader_.handle(), max);
  }
  uint32_t matched_writers() const { return dds::matched_writers(reader_.handle()); }
  bool wait_for_writers(uint32_t n, int64_t timeout_ns) const {
    return dds::wait_for_writers(reader_.handle(), n, timeout_ns);
  }
  EntityHandle handle() const { return reader_.handle(); }
  const topics::TopicSpec& spec() const { return topic_.spec(); }

 private:
  bool authentic(Owned<T>& sample) {
    if constexpr (Authenticated<T>) {
      return auth_->verify(topic_.spec(), guard_, sample.get()->auth, sample.get()) ==
             auth::Verdict::kAccepted;
    } else {
      return true;
    }
  }

  const dds_topic_descriptor_t* desc_;
  Topic<T> topic_;
  Entity reader_;
  AuthSession* auth_;
  auth::ReplayGuard guard_;
};

}  // namespace stereoball::dds
