#pragma once
// The bench's output: a readable table (with per-pair lines on request) or JSON with stable
// field names (README.md lists them).

#include <string>
#include <vector>

#include "real_stereo_run.hpp"
#include "real_stereo_score.hpp"
#include "real_stereo_set.hpp"

namespace stereoball::real_stereo {

/// What the run was, for the report's header.
struct ReportContext {
  const RealStereoSet* set = nullptr;
  const DetectorConfig* config = nullptr;
  std::string detector_base;  ///< the shipped detector file the overrides apply to
  RunOptions options;
};

/// Scores every pair with a detection (rows without one are run errors, already listed).
std::vector<PairScore> score_run(const RealStereoSet& set, const RunResult& run,
                                 const ScoreRules& rules = {});

/// The table; verbose adds one line per pair.
std::string format_table(const ReportContext& ctx, const RunResult& run,
                         const std::vector<PairScore>& scores, const Summary& summary,
                         bool verbose);

/// The JSON document (one object).
std::string format_json(const ReportContext& ctx, const RunResult& run,
                        const std::vector<PairScore>& scores, const Summary& summary);

}  // namespace stereoball::real_stereo
