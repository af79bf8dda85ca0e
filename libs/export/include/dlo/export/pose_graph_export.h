/// \file pose_graph_export.h
/// \brief The keyframe pose graph as an MRPT network of poses (.graph, read by `graph-slam`).
#pragma once

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <string>

#include "dlo/slam/slam_map.h"

namespace dlo {

/// Nodes are the keyframes (id = Keyframe::id) at their poses; edges are SlamMap::edges (pose of
/// `to` in `from`, with the information matrix in MRPT's x y z yaw pitch roll order). The root is
/// the first keyframe.
mrpt::graphs::CNetworkOfPoses3DInf toPoseGraph(const SlamMap& map);

/// Writes toPoseGraph() in the TORO/g2o text format of CNetworkOfPoses::saveToTextFile
/// (VERTEX3 / EDGE3 lines), atomically; `graph-slam --3d -i FILE` reads it.
/// \throws OutputError naming `path`.
void exportPoseGraph(const SlamMap& map, const std::string& path);

}  // namespace dlo
