#pragma once
// One headless Chromium showing the viewer page, for the benchmark (browser_client.mjs run
// by node): starts it, waits until the page draws images, and reads back the page's own
// capture -> drawn latencies and their stages.

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "common/util/result.hpp"

namespace stereoball::bench {

struct BrowserResult {
  uint64_t images = 0;
  uint64_t skipped = 0;  ///< pairs the page replaced by a newer one before decoding them
  std::vector<double> latencies_ms;
  std::vector<std::vector<double>> stages_ms;  ///< per drawn pair, the page's stages
};

class Browser {
 public:
  /// Whether a browser can run here; the error says what is missing (node, chromium, script).
  static Status available();
  /// Starts Chromium on url and waits (up to 120 s) until the page draws images.
  explicit Browser(const std::string& url);
  ~Browser();
  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;
  /// "" when the page is live, else what went wrong.
  const std::string& error() const { return error_; }
  /// Restarts the counts (the measurement starts now); false when the browser did not answer.
  bool mark();
  /// Images and latencies since the last mark (or since the page went live); ends the browser.
  std::optional<BrowserResult> finish();

 private:
  std::optional<std::string> read_line(double timeout_s);
  pid_t pid_ = -1;
  int to_node_ = -1, from_node_ = -1;
  std::string buffered_, error_;
};

}  // namespace stereoball::bench
