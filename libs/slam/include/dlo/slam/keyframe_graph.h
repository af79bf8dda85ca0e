/// \file keyframe_graph.h
/// \brief The keyframe pose graph on MRPT's CNetworkOfPoses3DInf and its SPA optimiser.
#pragma once

#include "dlo/slam/slam_map.h"

namespace dlo {

/// Optimises the keyframe poses of `map` with mrpt::graphslam::optimize_graph_spa_levmarq and
/// writes them back. Frames follow their keyframes (their poses are stored relative to them).
/// \return the final sum of squared errors.
double optimisePoseGraph(SlamMap& map, int max_iterations = 100);

/// Information matrix of an edge whose measured pose is `pose`, from a registration covariance
/// given in twist order (left perturbation). The result is in the order MRPT's graph-slam
/// optimiser applies it to the edge error SE3::log(D^-1 P1^-1 P2): [x y z rx ry rz], a right
/// perturbation of the edge pose; with standard deviations floored at `min_sigma_xy` metres and
/// `min_sigma_angle` radians: DLO's covariance from thousands of cells is optimistic, and an
/// over-confident edge would pin the graph.
Matrix6d edgeInformation(const Eigen::Isometry3d& pose, const Matrix6d& twist_covariance,
                         double min_sigma_xy, double min_sigma_angle);

}  // namespace dlo
