#include "dlo/slam/keyframe_graph.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/levmarq.h>

#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

namespace {

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
  Matrix6d cov = twistCovarianceToXYZYPR(pose, twist_covariance);
  cov = 0.5 * (cov + cov.transpose());
  for (int i = 0; i < 6; ++i) {
    const double floor = i < 3 ? min_sigma_xy : min_sigma_angle;
    cov(i, i) += floor * floor;
  }
  return cov.inverse();
}

}  // namespace dlo
