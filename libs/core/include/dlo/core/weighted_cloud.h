/// \file weighted_cloud.h
/// \brief Voxel-decimated clouds that keep enough statistics to rebuild exact mean heights.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <vector>

#include "dlo/core/point_cloud.h"

namespace dlo {

/// The centroid of the points of one voxel and how many there were. Rasterising weighted points
/// adds n to a cell's count and n * z to its height sum, so a decimated cloud gives the same
/// mean heights and the same 3-point rule as the raw scan (up to voxel-to-cell aliasing).
struct WeightedPoint {
  Eigen::Vector3f p = Eigen::Vector3f::Zero();
  std::uint32_t n = 0;
};

using WeightedCloud = std::vector<WeightedPoint>;

/// A weighted cloud seen from a pose: rasterising it maps each point by pose * p. Several views
/// rasterised together fuse clouds (e.g. recent keyframes into a local map) without copying
/// them into one frame first.
struct PosedCloud {
  const WeightedCloud* cloud = nullptr;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// Merges points into cubic voxels of side `voxel` metres (non-finite points are dropped).
/// Deterministic: voxels come out in the order their first point appears.
WeightedCloud voxelise(const PointCloud& points, double voxel);

/// Re-voxelises a weighted cloud (weights add, centroids are weighted means), e.g. to keep a
/// coarser long-term copy or to merge clouds expressed in one frame.
WeightedCloud voxelise(const WeightedCloud& points, double voxel);

namespace detail {
class VoxelHash;  ///< the open-addressing voxel table behind voxelise() and VoxelMerger
}  // namespace detail

/// Merges weighted clouds into voxels one cloud at a time, e.g. every keyframe of a long run
/// into one map cloud: memory grows with the voxels occupied, not with the clouds added. The
/// result equals voxelise() of all clouds concatenated (voxels in order of first occurrence).
class VoxelMerger {
 public:
  /// \param voxel side in metres, > 0.
  explicit VoxelMerger(double voxel);
  ~VoxelMerger();
  VoxelMerger(const VoxelMerger&) = delete;
  VoxelMerger& operator=(const VoxelMerger&) = delete;
  /// Adds every point of `cloud` (weights add, centroids are weighted means).
  void add(const WeightedCloud& cloud);
  /// The merged voxels so far.
  WeightedCloud result() const;

 private:
  std::unique_ptr<detail::VoxelHash> acc_;
  float inv_voxel_;
};

/// Every point as a voxel of its own (weight 1): a cloud kept whole where a weighted one is read.
WeightedCloud unitWeights(const PointCloud& points);

/// Applies a rigid transform to every centroid.
WeightedCloud transformed(const WeightedCloud& cloud, const Eigen::Isometry3d& pose);

/// Total number of original points represented.
std::uint64_t pointCount(const WeightedCloud& cloud);

}  // namespace dlo
