/// \file slam_map.h
/// \brief What a SLAM run produces: keyframes, every frame's pose, loop closures.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "dlo/core/rigid_transform.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/cloud_spill.h"

namespace dlo {

/// A keyframe: a scan kept for the local map, loop closure and map export.
struct Keyframe {
  int id = 0;         ///< index in SlamMap::keyframes
  int frame = 0;      ///< index of the scan it was made from
  double time = 0.0;  ///< seconds (scan reference time)
  /// Pose of the vehicle in the world (the first scan's vehicle frame); optimised when loops
  /// close.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  /// Deskewed points of the scan, vehicle frame, voxel-decimated with counts (long-term copy).
  /// Empty once `spilled`: then SlamMap::keyframeCloud() reads it back.
  WeightedCloud cloud;
  bool spilled = false;  ///< the cloud lies in SlamMap::spill at `slot`
  CloudSlot slot;
};

/// One processed scan.
struct FramePose {
  double time = 0.0;  ///< seconds
  int keyframe = 0;   ///< the keyframe it is anchored to
  /// Pose relative to that keyframe (from odometry); the world pose is
  /// keyframes[keyframe].pose * relative, so optimising keyframes moves every frame.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Pose from odometry alone (odometry frame), kept to measure what loop closure changed.
  Eigen::Isometry3d odometry = Eigen::Isometry3d::Identity();
  bool degenerate = false;        ///< the registration flagged an unobservable direction
  double rms_height_error = 0.0;  ///< metres
};

/// An edge between two keyframes: odometry (consecutive) or loop closure.
struct PoseEdge {
  int from = 0;  ///< keyframe id
  int to = 0;    ///< keyframe id
  /// Pose of `to` in the frame of `from`.
  Eigen::Isometry3d relative = Eigen::Isometry3d::Identity();
  /// Information matrix in the order MRPT's graph-slam uses it (CPose3DPDFGaussianInf::cov_inv
  /// applied to the error SE3::log(D^-1 P1^-1 P2)): [x y z rx ry rz] of a right perturbation of
  /// `relative`.
  Matrix6d information = Matrix6d::Identity();
  bool loop = false;
};

/// A loop-closure candidate and the verdict of its verification.
struct LoopCandidate {
  int from = 0;  ///< older keyframe
  int to = 0;    ///< newer keyframe
  bool accepted = false;
  std::string reason;  ///< why it was rejected, or "accepted"
  double rms_height_error = 0.0;
  double correction = 0.0;  ///< metres between the guess and the verified pose
  /// Verified from the guess alone (LoopSearch::kFromGuess), not by the coarse search.
  bool tracked = false;
};

/// The state of a SLAM run; what the exporters write.
struct SlamMap {
  std::vector<Keyframe> keyframes;
  std::vector<FramePose> frames;
  std::vector<PoseEdge> edges;
  std::vector<LoopCandidate> loop_candidates;

  /// Keyframe clouds moved out of memory (shared by copies of the map; created on first use).
  std::shared_ptr<CloudSpill> spill;

  /// World pose of frame i.
  Eigen::Isometry3d framePose(size_t i) const {
    return keyframes[frames[i].keyframe].pose * frames[i].relative;
  }
  /// The cloud of keyframe i: the keyframe's own when in memory, otherwise read from the spill
  /// file into `buffer`. The reference is valid until `buffer` or the keyframe changes.
  const WeightedCloud& keyframeCloud(size_t i, WeightedCloud& buffer) const;
  /// Moves keyframe i's cloud to the spill file and frees its memory (no-op if already there).
  void spillKeyframeCloud(size_t i);
  /// Bytes of keyframe clouds held in memory.
  size_t residentCloudBytes() const;
};

}  // namespace dlo
