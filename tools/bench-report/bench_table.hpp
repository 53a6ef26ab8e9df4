// The acceptance benchmarks that `stereoball bench report` runs or reads: one entry per bench.
#pragma once

#include <string>
#include <vector>

namespace stereoball::bench_report {

// One benchmark of the report: how to run it and what it measures.
struct BenchEntry {
  std::string name;               // file stem of its outputs in the output folder (NAME.txt, ...)
  std::string title;              // heading in docs/benchmarks.md
  std::string program;            // executable beside stereoball-bench-report
  std::vector<std::string> args;  // arguments, without --json
  bool writes_json = false;       // takes `--json FILE`
  std::string measures;           // one sentence: what the figures are
  std::string data;               // which data the figures come from, and what was tuned on it
  bool cheap = false;             // run by default (minutes on a shared 2-core machine)
};

// Every benchmark the report knows, in report order. Adding a bench is one entry here.
const std::vector<BenchEntry>& bench_table();

// The entry named NAME, or nullptr.
const BenchEntry* find_bench(const std::string& name);

// The command a user types to reproduce the entry: `stereoball bench X ARGS...`.
std::string user_command(const BenchEntry& entry);

}  // namespace stereoball::bench_report
