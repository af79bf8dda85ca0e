/// \file method_run.h
/// \brief Running one method over a scan sequence: per-frame timing, trajectory, peak memory,
/// each method in its own forked process.
#pragma once

#include <string>
#include <vector>

#include "dlo/bench/method_registry.h"
#include "dlo/metrics/trajectory.h"
#include "dlo/mrpt/scan_source.h"

namespace dlo::bench {

/// What one method produced on one sequence.
struct MethodRun {
  std::string method;              ///< MethodSpec::name
  metrics::Trajectory trajectory;  ///< final estimate, one pose per processed scan
  /// Milliseconds of OdometryMethod::process() per scan: points in, pose out; reading and
  /// decoding the scan are not included.
  std::vector<double> ms;
  double peak_memory_mb = 0.0;      ///< peak resident memory of the process that ran it
  double baseline_memory_mb = 0.0;  ///< resident memory of that process before the first scan
  std::string error;                ///< empty when the run completed
  std::string input_warning;        ///< where the input broke, if it did (scans before it count)
  int passes = 1;                   ///< runs combined into this one (combinePasses())
  /// Largest distance between the positions the passes gave one scan (0: they agree).
  double pass_disagreement_m = 0.0;
};

/// Feeds the first `max_frames` scans of `source` (all if negative) to a new instance of `spec`
/// in this process. Exceptions from the method are caught into MethodRun::error. Peak memory is
/// this process's, so it is only meaningful in a fresh process (see runMethodIsolated()).
MethodRun runMethod(const MethodSpec& spec, ScanSource& source, long max_frames,
                    bool progress = false);

/// runMethod() in a forked child process that opens `rawlog` itself (the page cache makes the
/// second reading cheap, and reading is not timed), so that each method's peak memory is its
/// own: the child's high-water mark is reset right after the fork and read at the end. The
/// child sends its result back through a pipe; a child that crashes gives a MethodRun whose
/// error says how it ended. Call it from a single-threaded process (fork() copies one thread).
MethodRun runMethodIsolated(const MethodSpec& spec, const std::string& rawlog,
                            const ScanSourceOptions& options, long max_frames,
                            bool progress = false);

/// Several runs of one method over the same scans (dlo-bench --repeat) as one run: each scan's
/// time is the median of its times in the passes (of the two middle ones for an even count), so
/// that a pass slowed by the machine's other work moves a scan's time only if most passes were;
/// the trajectory, warning and baseline memory are the first pass's, the peak memory the
/// largest, and pass_disagreement_m how far apart the passes placed any one scan. The first
/// pass with an error is returned as it is; passes of different lengths are cut to the
/// shortest. Throws std::invalid_argument for no pass.
MethodRun combinePasses(const std::vector<MethodRun>& passes);

}  // namespace dlo::bench
