#include "dlo/slam/keyframe_graph.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

namespace {

/// Largest standard deviations an edge may claim (see edgeInformation()).
constexpr double kMaxSigmaXY = 1.0;                  // metres
constexpr double kMaxSigmaAngle = 5.0 * M_PI / 180;  // radians

/// Nodes = keyframe poses, edges = odometry and accepted loop edges, node 0 fixed. (The
/// exporter builds the same graph for keyframes.graph, from the optimised poses.)
mrpt::graphs::CNetworkOfPoses3DInf buildPoseGraph(const SlamMap& map) {
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  for (const Keyframe& k : map.keyframes) {
    graph.nodes[static_cast<mrpt::graphs::TNodeID>(k.id)] = toCPose3D(k.pose);
  }
  for (const PoseEdge& e : map.edges) {
    mrpt::poses::CPose3DPDFGaussianInf edge;
    edge.mean = toCPose3D(e.relative);
    edge.cov_inv = mrpt::math::CMatrixDouble66(e.information);
    graph.insertEdge(static_cast<mrpt::graphs::TNodeID>(e.from),
                     static_cast<mrpt::graphs::TNodeID>(e.to), edge);
  }
  graph.root = 0;
  return graph;
}

}  // namespace

double optimisePoseGraph(SlamMap& map, int max_iterations) {
  if (map.keyframes.size() < 2) return 0.0;
  mrpt::graphs::CNetworkOfPoses3DInf graph = buildPoseGraph(map);
  mrpt::graphslam::TResultInfoSpaLevMarq info;
  mrpt::containers::yaml params = mrpt::containers::yaml::Map();
  params["max_iterations"] = static_cast<uint64_t>(max_iterations);
  mrpt::graphslam::optimize_graph_spa_levmarq(graph, info, nullptr, params);
  for (Keyframe& k : map.keyframes) {
    k.pose = toIsometry(graph.nodes.at(static_cast<mrpt::graphs::TNodeID>(k.id)));
  }
  return info.final_total_sq_error;
}

Matrix6d edgeInformation(const Eigen::Isometry3d& pose, const Matrix6d& twist_covariance,
                         double min_sigma_xy, double min_sigma_angle) {
  // MRPT's SPA measures an edge's error as SE3::log(D^-1 P1^-1 P2), a right perturbation of the
  // measured pose D in the order [x y z rx ry rz], and weighs it with the edge's cov_inv as is.
  // The registration gives a left perturbation exp(xi) D; the two are related by the adjoint:
  // eps = Ad(D^-1) xi.
  const Eigen::Isometry3d inv = pose.inverse();
  const Eigen::Matrix3d R = inv.linear();
  const Eigen::Vector3d t = inv.translation();
  Eigen::Matrix3d tx;
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  Matrix6d adjoint = Matrix6d::Zero();
  adjoint.topLeftCorner<3, 3>() = R;
  adjoint.topRightCorner<3, 3>() = tx * R;
  adjoint.bottomRightCorner<3, 3>() = R;
  Matrix6d cov = adjoint * twist_covariance * adjoint.transpose();
  cov = 0.5 * (cov + cov.transpose());
  // Unobserved directions (3-DoF z, roll, pitch; degenerate axes) carry a variance of 1e6,
  // which leaves the graph with a near null space in which the optimiser stalls. Cap them at a
  // weak but finite prior: the odometry's value, give or take kMaxSigmaXY / kMaxSigmaAngle.
  Eigen::SelfAdjointEigenSolver<Matrix6d> es(cov);
  Vector6d lambda = es.eigenvalues();
  const Matrix6d& V = es.eigenvectors();
  for (int i = 0; i < 6; ++i) {
    // The cap of a direction follows its mix of translation and rotation.
    const double rot = V.col(i).tail<3>().squaredNorm();
    const double cap =
        (1.0 - rot) * kMaxSigmaXY * kMaxSigmaXY + rot * kMaxSigmaAngle * kMaxSigmaAngle;
    lambda(i) = std::min(std::max(lambda(i), 0.0), cap);
  }
  cov = V * lambda.asDiagonal() * V.transpose();
  for (int i = 0; i < 6; ++i) {
    const double floor = i < 3 ? min_sigma_xy : min_sigma_angle;
    cov(i, i) += floor * floor;
  }
  return cov.inverse();
}

}  // namespace dlo
