/// \file slam_pipeline.h
/// \brief The whole SLAM pipeline: odometry, keyframes, pose graph, loop closure.
#pragma once

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
  std::vector<double> loop;  ///< loop search, verification and graph optimisation
};

/// Counters of a run.
struct PipelineCounters {
  size_t frames = 0;
  size_t empty_frames = 0;  ///< scans without a valid cell (pose from the motion prior)
  size_t degenerate_frames = 0;
  size_t loops_accepted = 0;
  size_t loops_rejected = 0;
  size_t optimisations = 0;
};

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
  const SlamParams& params() const { return params_; }

  /// Verifies one loop candidate between two existing keyframes with the given guess (pose of
  /// `to` in `from`) and, if accepted, adds the edge and optimises. Exposed for tests and tools.
  LoopCandidate tryLoop(int from, int to, const Eigen::Isometry3d& guess);

 private:
  void addKeyframe(double time, const OdometryStep& step);
  void searchLoops(int newest);

  SlamParams params_;
  LidarOdometry odometry_;
  LoopCloser loops_;
  SlamMap map_;
  PipelineTimings timings_;
  PipelineCounters counters_;
  std::vector<double> path_length_;             ///< metres travelled up to each keyframe
  std::vector<Eigen::Isometry3d> kf_odometry_;  ///< odometry-frame pose of each keyframe
  Eigen::Isometry3d last_odometry_ = Eigen::Isometry3d::Identity();
  double travelled_ = 0.0;
  int last_loop_keyframe_ = -1000;
};

}  // namespace dlo
