/// \file slam_pipeline.h
/// \brief The whole SLAM pipeline: odometry, keyframes, pose graph, loop closure.
#pragma once

#include <optional>
#include <utility>
#include <vector>

#include "dlo/slam/lidar_odometry.h"
#include "dlo/slam/loop_closure.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// Per-frame processing times, milliseconds, one entry per processed scan.
struct PipelineTimings {
  std::vector<double> total;  ///< points to pose (file reading excluded)
  std::vector<double> deskew;
  std::vector<double> grid;
  std::vector<double> gradients;
  std::vector<double> selection;
  std::vector<double> solve;
  std::vector<double> keyframe;
  std::vector<double> local_map;
  std::vector<double> ground;  ///< odometry.levelling: the ground's fit and alignments
  std::vector<double> loop;    ///< loop search, verification and graph optimisation
};

/// Counters of a run.
struct PipelineCounters {
  size_t frames = 0;
  size_t empty_frames = 0;  ///< scans without a valid cell (pose from the motion prior)
  size_t degenerate_frames = 0;
  /// Scans whose registration disagreed with the prediction and was decided by registering
  /// from other starts (OdometryStep::starts > 1) ...
  size_t multi_start_frames = 0;
  /// ... of which another start than the prediction gave the pose ...
  size_t alternative_frames = 0;
  /// ... and of which the prediction fitted best and was kept (OdometryStep::rejected).
  size_t prediction_kept_frames = 0;
  /// Scans registered again from a heading that fitted the coarsest level better
  /// (OdometryStep::turn_searched) ...
  size_t turn_searched_frames = 0;
  /// ... of which that registration stood for the first (OdometryStep::turn_found).
  size_t turn_found_frames = 0;
  /// Scans deskewed with other yaw rates where a registration contradicted the prediction
  /// (OdometryStep::rate_searched) ...
  size_t rate_searched_frames = 0;
  /// ... of which one of those rates fitted best (OdometryStep::rate_found).
  size_t rate_found_frames = 0;
  /// Scans whose registration could not observe a direction along which the prediction was
  /// uncertain, registered again from starts along it (OdometryStep::search_starts) ...
  size_t searched_frames = 0;
  /// ... of which one of those starts gave the pose (OdometryStep::searched).
  size_t search_found_frames = 0;
  /// Scans whose positions a search's velocity moved afterwards (OdometryStep::backfill).
  size_t backfilled_frames = 0;
  /// Scans whose z, roll and pitch were measured from their ground (OdometryStep::levelled).
  size_t levelled_frames = 0;
  /// Scans by where their per-point times came from (PointTimeSource): measured, estimated
  /// from the azimuths with the start read off the point order or from the sweep_* keys.
  size_t times_measured = 0;
  size_t times_from_order = 0;
  size_t times_from_params = 0;
  /// The revolution period the last scan with estimated times assumed (seconds; 0: none).
  double sweep_period = 0.0;
  size_t loops_accepted = 0;
  size_t loops_rejected = 0;
  size_t optimisations = 0;
  /// accepted loops the graph already satisfied: edge added, no optimisation needed
  size_t loops_consistent = 0;
  /// accepted loops verified from the guess alone (LoopSearch::kFromGuess)
  size_t loops_tracked = 0;
  /// verifications from the guess that did not pass, each followed by the lattice search
  size_t loops_untracked = 0;
};

/// Resident memory at one point of a run, to show that it does not grow with the scans.
struct MemorySample {
  size_t frame = 0;          ///< scans processed so far
  double resident_mb = 0.0;  ///< resident set size of the process (VmRSS)
  size_t keyframes = 0;      ///< keyframes held at that point
  double keyframe_mb = 0.0;  ///< what their clouds occupy in memory: the part that may grow
  double spilled_mb = 0.0;   ///< keyframe clouds moved to the temporary file (not resident)
};

/// Growth of the resident memory that the keyframes do not explain, KiB per scan: the
/// least-squares slope of (resident_mb - keyframe_mb) over the samples after the first (which
/// include start-up). 0 with fewer than three samples. A pipeline that kept anything per raw
/// scan (a cloud, a grid) would show tens to hundreds of KiB per scan.
double unexplainedGrowthKbPerFrame(const std::vector<MemorySample>& samples);

/// Streams scans through odometry, keyframe creation, loop-closure search and verification, and
/// pose-graph optimisation. Memory grows with the keyframes (decimated clouds), not with the
/// scans.
class SlamPipeline {
 public:
  explicit SlamPipeline(const SlamParams& params);

  /// Processes one scan (vehicle frame at `time`, optional per-point times relative to it).
  void process(double time, const PointCloud& points, const std::vector<float>& point_times);

  /// Re-runs the pose-graph optimisation (done automatically after each accepted loop).
  void optimise();

  const SlamMap& map() const { return map_; }
  SlamMap& map() { return map_; }
  const PipelineTimings& timings() const { return timings_; }
  const PipelineCounters& counters() const { return counters_; }
  const SlamParams& params() const { return odometry_.params(); }
  /// Memory after the first scan, then every kMemorySampleInterval scans.
  const std::vector<MemorySample>& memorySamples() const { return memory_; }
  /// Takes a memory sample now (also done automatically; call it after the last scan).
  void sampleMemory();
  static constexpr size_t kMemorySampleInterval = 50;

  /// Verifies one loop candidate between two existing keyframes with the given guess (pose of
  /// `to` in `from`) and, if accepted, adds the edge and optimises. Exposed for tests and tools.
  LoopCandidate tryLoop(int from, int to, const Eigen::Isometry3d& guess,
                        LoopSearch search = LoopSearch::kLattice);

 private:
  /// `pose`: the step's pose in the smoothed odometry frame (odometry_shift_ applied).
  void addKeyframe(double time, const OdometryStep& step, const Eigen::Isometry3d& pose);
  /// Moves the scans before this one, and the keyframes among them, by step.backfill, and
  /// every later scan with them (odometry_shift_).
  void applyBackfill(const OdometryStep& step);
  void searchLoops(int newest);
  /// Moves the clouds of all but the newest resident_keyframes keyframes to the spill file.
  void spillOldKeyframes();

  SlamParams params_;
  LidarOdometry odometry_;
  LoopCloser loops_;
  SlamMap map_;
  PipelineTimings timings_;
  PipelineCounters counters_;
  std::vector<MemorySample> memory_;
  std::vector<double> path_length_;             ///< metres travelled up to each keyframe
  std::vector<Eigen::Isometry3d> kf_odometry_;  ///< odometry-frame pose of each keyframe
  /// What the backfills so far moved the odometry frame by (a translation): the pipeline's
  /// odometry poses are the odometry's moved by it.
  Eigen::Vector3d odometry_shift_ = Eigen::Vector3d::Zero();
  Eigen::Isometry3d last_odometry_ = Eigen::Isometry3d::Identity();
  double travelled_ = 0.0;
  int last_loop_keyframe_ = -1000;  ///< newest keyframe of the last accepted loop
  int last_loop_from_ = -1000;      ///< its older keyframe
  /// Path length at the last lattice search that closed no loop (loop.retry_distance).
  double last_failed_search_ = -1e9;
  /// loop.confirm: the first loop of a revisit, verified but not yet added, waiting for a later
  /// keyframe's loop to agree (its entry in map_.loop_candidates says so meanwhile).
  struct PendingLoop {
    PoseEdge edge;
    size_t candidate = 0;  ///< index in map_.loop_candidates
    /// The keyframes its two sides were made of (LoopCloser::submapWindow()): a confirmation
    /// must share none of them, or it repeats the same evidence.
    std::pair<int, int> from_window, to_window;
  };
  std::optional<PendingLoop> pending_loop_;
  /// Whether two verified loops (edges between keyframes of map_) put the vehicle in the same
  /// basin: the first carried to the second's keyframes by their poses in the graph.
  bool sameBasin(const PoseEdge& a, const PoseEdge& b) const;
};

}  // namespace dlo
