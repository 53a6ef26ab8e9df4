#pragma once
// Where a frame's time goes in the node, for finding a slow frame's cause: the wait before its
// processing, decoding, the search with the pipeline's shared jobs (each thread's part, the
// caller's wait for the helper) and searches, publishing, and each thread's CPU and run-queue
// wait (the kernel's schedstat). One CSV line per frame into a file given on the command line;
// off by default (nothing is measured then).

#include <cstdint>
#include <fstream>
#include <mutex>
#include <string>
#include <vector>

#include "ball_detector/node/task_helper.hpp"
#include "ball_detector/pipeline/search/search_strategy.hpp"

namespace stereoball::ball_detector {

/// A thread's time on a core and waiting for one (runnable), ns, from /proc/self/task/TID.
struct ThreadSched {
  std::int64_t run_ns = 0;
  std::int64_t wait_ns = 0;
};
/// tid's schedstat; zeros when the kernel does not keep it.
ThreadSched thread_sched(int tid);

/// One search of a frame as the pipeline's observer saw it, ns.
struct SearchTimes {
  SearchPath path = SearchPath::kWholeFrame;
  bool on_helper = false;  ///< run on the task helper's thread
  std::int64_t start_ns = 0, end_ns = 0, cpu_ns = 0;
};

/// The stages of the frame being processed; written as one CSV line when it ends.
class FrameTimesLog {
 public:
  /// Opens path for writing (truncated) with the column header; check ok().
  explicit FrameTimesLog(const std::string& path);
  /// Whether the file could be written.
  bool ok() const { return out_.good(); }

  /// A frame taken from the reader: its capture and publication stamps (wall clock, ns); the
  /// task helper's thread id.
  void arrived(std::uint64_t seq, std::int64_t capture_ns, std::int64_t published_ns,
               int helper_tid);
  /// Its eyes decoded; the search starts.
  void decoded();
  /// The search is done; publishing starts.
  void stepped();
  /// The pipeline's observer: a search started or ended on the calling thread.
  void search(SearchPath path, bool started);
  /// The detection is published: writes the line with the helper's jobs of the frame.
  void published(int status, SearchPath last_search, const std::vector<JobTimes>& jobs);

 private:
  std::ofstream out_;
  int helper_tid_ = 0, main_tid_ = 0;
  std::uint64_t seq_ = 0;
  std::int64_t capture_ns_ = 0, published_ns_ = 0, arrived_wall_ns_ = 0;
  std::int64_t start_ns_ = 0, decoded_ns_ = 0, stepped_ns_ = 0;
  ThreadSched main_start_, helper_start_;
  std::mutex searches_mutex_;  // the observer is told on both threads
  std::vector<SearchTimes> searches_;
};

}  // namespace stereoball::ball_detector
