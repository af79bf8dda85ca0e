#include "dlo/export/pose_graph_export.h"

#include <fstream>

#include "dlo/files/atomic_file.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

mrpt::graphs::CNetworkOfPoses3DInf toPoseGraph(const SlamMap& map) {
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  for (const Keyframe& kf : map.keyframes) {
    graph.nodes[static_cast<mrpt::graphs::TNodeID>(kf.id)] = toCPose3D(kf.pose);
  }
  if (!map.keyframes.empty()) graph.root = static_cast<mrpt::graphs::TNodeID>(map.keyframes[0].id);
  for (const PoseEdge& e : map.edges) {
    mrpt::poses::CPose3DPDFGaussianInf constraint;
    constraint.mean = toCPose3D(e.relative);
    constraint.cov_inv = mrpt::math::CMatrixDouble66(e.information);
    graph.insertEdge(static_cast<mrpt::graphs::TNodeID>(e.from),
                     static_cast<mrpt::graphs::TNodeID>(e.to), constraint);
  }
  return graph;
}

void exportPoseGraph(const SlamMap& map, const std::string& path) {
  const mrpt::graphs::CNetworkOfPoses3DInf graph = toPoseGraph(map);
  writeAtomically(path, [&](const std::string& temp) {
    // saveToTextFile() writes with the stream's default 6 significant digits, i.e. centimetres
    // at 1 km; writeAsText() is the same writer on a stream whose precision we choose.
    std::ofstream out(temp);
    if (!out) throw std::runtime_error("cannot create '" + temp + "'");
    out.precision(12);
    graph.writeAsText(out);
    out.close();
    if (!out) throw std::runtime_error("writing '" + temp + "' failed (disk full?)");
  });
}

}  // namespace dlo
