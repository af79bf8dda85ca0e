/// \file trajectory.h
/// \brief A timestamped sequence of poses, the unit every metric works on.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace dlo::metrics {

/// Poses of a vehicle over time. times[i] (seconds) is the stamp of poses[i]; both vectors have
/// the same length. Poses map vehicle coordinates to world coordinates (world = pose * vehicle).
struct Trajectory {
  std::vector<double> times;
  std::vector<Eigen::Isometry3d> poses;

  size_t size() const { return poses.size(); }
  bool empty() const { return poses.empty(); }
  void push_back(double t, const Eigen::Isometry3d& pose) {
    times.push_back(t);
    poses.push_back(pose);
  }
};

/// Cumulative path length: distances[i] is the length of the polyline through the positions of
/// poses 0..i (distances[0] = 0), in metres.
std::vector<double> pathDistances(const std::vector<Eigen::Isometry3d>& poses);

}  // namespace dlo::metrics
