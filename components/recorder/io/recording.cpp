#include "recorder/io/recording.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

namespace stereoball::recorder {

namespace {
// Queue accounting per item on top of its payload, so tiny messages are bounded too.
constexpr uint64_t kItemOverheadBytes = 64;
}  // namespace

Status RecordingParams::validate() const {
  if (path.empty()) return Error{"path must not be empty"};
  if (split_size_bytes != 0 && split_size_bytes < (1u << 20)) {
    return Error{"split_size_bytes must be 0 (off) or >= 1048576, got " +
                 std::to_string(split_size_bytes)};
  }
  if (split_duration_ns < 0) return Error{"split_duration_ns must be >= 0 (0 = off)"};
  if (queue_limit_bytes < (1u << 20)) {
    return Error{"queue_limit_bytes must be >= 1048576, got " + std::to_string(queue_limit_bytes)};
  }
  if (chunk_flush_period_ns < 1'000'000) return Error{"chunk_flush_period_ns must be >= 1 ms"};
  return writer.validate();
}

Recording::Recording(const RecordingParams& params, std::vector<RecordedTopic> topics)
    : params_(params),
      topics_(std::move(topics)),
      counters_(topics_.size()),
      sequences_(topics_.size(), 0) {}

Result<std::unique_ptr<Recording>> Recording::start(const RecordingParams& params,
                                                    std::vector<RecordedTopic> topics) {
  if (auto bad = params.validate(); !bad) return Error{bad.error()};
  if (topics.empty()) return Error{"no topics to record"};
  std::unique_ptr<Recording> rec(new Recording(params, std::move(topics)));
  if (auto err = rec->open_file(); !err) return Error{err.error()};
  rec->thread_ = std::thread([r = rec.get()] { r->run(); });
  return rec;
}

Recording::~Recording() {
  stop();
}

std::string Recording::file_path(size_t index) const {
  if (params_.split_size_bytes == 0 && params_.split_duration_ns == 0) return params_.path;
  std::filesystem::path p(params_.path);
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, "_%03zu", index);
  const std::string ext = p.has_extension() ? p.extension().string() : ".mcap";
  return (p.parent_path() / (p.stem().string() + suffix + ext)).string();
}

Status Recording::open_file() {
  std::string path;
  {
    std::lock_guard lock(mutex_);
    path = file_path(files_.size());
  }
  auto sink = FileSink::create(path);
  if (!sink) return Error{sink.error()};
  sink_ = std::move(*sink);
  auto spill = FileSpill::create(std::filesystem::path(path).parent_path().string());
  if (!spill) return Error{spill.error()};
  index_spill_ = std::move(*spill);
  writer_ = std::make_unique<McapWriter>(params_.writer);
  if (auto err = writer_->open(*sink_, index_spill_.get()); !err) return err;
  channel_ids_.clear();
  for (const auto& t : topics_) {
    const auto schema = writer_->add_schema(t.type_name, "omgidl", t.schema_text);
    if (!schema) return Error{schema.error()};
    const auto channel = writer_->add_channel(schema.value(), t.topic, "cdr");
    if (!channel) return Error{channel.error()};
    channel_ids_.push_back(channel.value());
  }
  file_has_messages_ = false;
  std::lock_guard lock(mutex_);
  files_.push_back(path);
  return {};
}

Status Recording::close_file() {
  if (!writer_) return {};
  Status err = writer_->status();
  if (err.ok()) err = writer_->close();
  writer_.reset();
  index_spill_.reset();
  sink_.reset();
  return err;
}

void Recording::fail(const std::string& what) {
  std::lock_guard lock(mutex_);
  if (failure_.ok()) failure_ = Error{what};
}

Status Recording::write_item(const Item& item) {
  const bool split_by_size =
      params_.split_size_bytes != 0 && writer_->stats().file_bytes >= params_.split_size_bytes;
  const bool split_by_time = params_.split_duration_ns != 0 && file_has_messages_ &&
                             item.log_ns >= file_first_log_ns_ + params_.split_duration_ns;
  if (file_has_messages_ && (split_by_size || split_by_time)) {
    if (auto err = close_file(); !err) return err;
    if (auto err = open_file(); !err) return err;
  }
  if (!file_has_messages_) {
    file_first_log_ns_ = item.log_ns;
    file_has_messages_ = true;
  }
  return writer_->write(
      {channel_ids_[item.topic], item.sequence, item.log_ns, item.publish_ns, item.cdr});
}

void Recording::run() {
  using Clock = std::chrono::steady_clock;
  auto last_flush = Clock::now();
  bool unflushed = false;
  while (true) {
    std::optional<Item> item;
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, std::chrono::milliseconds(100),
                     [&] { return stopping_ || !queue_.empty(); });
      if (!queue_.empty()) {
        item = std::move(queue_.front());
        queue_.pop_front();
        queued_bytes_ -= item->cdr.size() + kItemOverheadBytes;
      } else if (stopping_) {
        break;
      }
    }
    if (item && status().ok()) {
      if (auto err = write_item(*item); !err) {
        fail(err.error());
      } else {
        std::lock_guard lock(mutex_);
        ++counters_[item->topic].messages;
        counters_[item->topic].bytes += item->cdr.size();
        unflushed = true;
      }
    } else if (item) {
      std::lock_guard lock(mutex_);
      ++counters_[item->topic].dropped;
    }
    // Slow topics must not sit in memory for long: a crash would lose them.
    const auto now = Clock::now();
    if (unflushed && status().ok() &&
        now - last_flush >= std::chrono::nanoseconds(params_.chunk_flush_period_ns)) {
      if (auto err = writer_->flush_chunk(); !err) fail(err.error());
      last_flush = now;
      unflushed = false;
    }
  }
}

bool Recording::push(size_t topic_index, std::vector<uint8_t> cdr, uint64_t log_time_ns,
                     uint64_t publish_time_ns) {
  std::lock_guard lock(mutex_);
  if (topic_index >= topics_.size()) return false;
  const uint64_t cost = cdr.size() + kItemOverheadBytes;
  if (!failure_.ok() || stopping_ || queued_bytes_ + cost > params_.queue_limit_bytes) {
    ++counters_[topic_index].dropped;
    return false;
  }
  queued_bytes_ += cost;
  queue_.push_back(
      Item{topic_index, sequences_[topic_index]++, log_time_ns, publish_time_ns, std::move(cdr)});
  wake_.notify_one();
  return true;
}

std::vector<TopicCounters> Recording::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

uint64_t Recording::queued_bytes() const {
  std::lock_guard lock(mutex_);
  return queued_bytes_;
}

Status Recording::status() const {
  std::lock_guard lock(mutex_);
  return failure_;
}

std::vector<std::string> Recording::files() const {
  std::lock_guard lock(mutex_);
  return files_;
}

Status Recording::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return failure_;
    stopping_ = true;
  }
  wake_.notify_one();
  if (thread_.joinable()) thread_.join();
  if (status().ok()) {
    if (auto err = close_file(); !err) fail(err.error());
  } else {
    writer_.reset();
    index_spill_.reset();
    sink_.reset();
  }
  return status();
}

}  // namespace stereoball::recorder
