#pragma once
// The replay tests' shared plumbing: one node started on its own partition of the test's
// domain, the recording played into it with stereoball-play, its output topic collected with
// deadlines, and the committed references (tests/replay/reference/) read, compared with, or
// rewritten (SB_REGENERATE_REFERENCES=1). What each test compares stays in the test.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/dds/participant.hpp"
#include "common/dds/reader.hpp"
#include "process.hpp"
#include "stereoball/topics.hpp"

namespace stereoball::replay {

/// Playback rate of stereoball-play: slower than recorded so the nodes are never overrun.
inline constexpr const char* kPlayRate = "0.25";

/// Argument vector of node `name` (build/bin) with config file config_file (from
/// SB_REPLAY_CONFIG_DIR, default config/) on the test's domain and partition.
std::vector<std::string> node_argv(const std::string& name, const std::string& config_file,
                                   const std::string& partition);
/// Argument vector of stereoball-play of topics of recording into the test's domain and
/// partition (rate kPlayRate, waiting up to 2 s for readers).
std::vector<std::string> play_argv(const std::string& recording,
                                   const std::vector<std::string>& topics,
                                   const std::string& partition);
/// Calls poll every 5 ms while play runs (60 s at most), then for linger after it exits.
void pump(testing::Process& play, const std::function<void()>& poll,
          std::chrono::milliseconds linger);
/// qos with a history of 1000 and no deadline, so a reader keeps every output sample.
topics::QosSpec keep_all(topics::QosSpec qos);

/// One node under replay: a reader of its output topic on a fresh partition of the test's
/// domain, the node process and the stereoball-play process. Processes still running are
/// killed on destruction (play first, then the node).
template <typename T>
class NodeReplay {
 public:
  /// A reader of output (nothing started yet); recording is the MCAP file to play.
  NodeReplay(std::string recording, const topics::Topic<T>& output)
      : recording_(std::move(recording)),
        reader_(participant_, output, keep_all(output.spec.qos)) {}

  /// Starts node `name` with config_file and waits (15 s) until it writes the output topic.
  /// Fatal failure (with the node's output) otherwise: call in ASSERT_NO_FATAL_FAILURE.
  void start_node(const std::string& name, const std::string& config_file) {
    node_.emplace(testing::Process::start(node_argv(name, config_file, partition_)));
    ASSERT_TRUE(reader_.wait_for_writers(1, 15'000'000'000)) << node_->output();
  }

  /// Plays topics of the recording into the node, calling poll as pump() does; fatal failure
  /// unless play then exits with 0 within 5 s: call in ASSERT_NO_FATAL_FAILURE.
  void play(const std::vector<std::string>& topics, const std::function<void()>& poll,
            std::chrono::milliseconds linger) {
    play_.emplace(testing::Process::start(play_argv(recording_, topics, partition_)));
    pump(*play_, poll, linger);
    ASSERT_EQ(play_->wait_for_exit(std::chrono::seconds(5)), 0) << play_->output();
  }

  /// play() that appends to_row(sample) to rows for every output sample, in arrival order.
  void collect(const std::vector<std::string>& topics,
               const std::function<nlohmann::json(const T&)>& to_row,
               std::chrono::milliseconds linger, nlohmann::json& rows) {
    play(
        topics,
        [&] {
          for (auto& s : take()) rows.push_back(to_row(*s.get()));
        },
        linger);
  }

  /// Output samples received since the last call (at most 64, oldest first).
  std::vector<dds::Owned<T>> take() { return reader_.take(64); }

  /// Everything the node printed so far (empty before start_node).
  std::string node_output() const { return node_ ? node_->output() : std::string(); }

 private:
  std::string recording_;
  std::string partition_ = testing::unique_partition();
  dds::DomainParticipant participant_{{testing::test_domain(), partition_}};
  dds::DataReader<T> reader_;
  std::optional<testing::Process> node_;
  std::optional<testing::Process> play_;
};

/// True when SB_REGENERATE_REFERENCES=1: the tests rewrite their references from this run.
bool regenerate_references();
/// Path of reference file name (tests/replay/reference/name) in the source tree.
std::string reference_path(const std::string& name);
/// The reference name, first rewritten from actual when regenerate_references(); a discarded
/// value (neither array nor object) when missing or unreadable.
nlohmann::json reference(const std::string& name, const nlohmann::json& actual);

/// Differences between actual and reference frames keyed by "seq"; only frames in both are
/// compared (common: how many). exact: fields that must be equal; toleranced: {field,
/// tolerance} for numbers or equally long arrays of numbers.
std::vector<std::string> compare(const nlohmann::json& actual, const nlohmann::json& reference,
                                 const std::vector<std::string>& exact,
                                 const std::vector<std::pair<std::string, double>>& toleranced,
                                 std::size_t& common);
/// The first n differences, one a line.
std::string first_diffs(const std::vector<std::string>& diffs, std::size_t n = 10);

}  // namespace stereoball::replay
