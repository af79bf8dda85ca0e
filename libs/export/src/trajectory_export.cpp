#include "dlo/export/trajectory_export.h"

#include "dlo/metrics/trajectory_io.h"

namespace dlo {

metrics::Trajectory frameTrajectory(const SlamMap& map) {
  metrics::Trajectory t;
  for (size_t i = 0; i < map.frames.size(); ++i) t.push_back(map.frames[i].time, map.framePose(i));
  return t;
}

// The metrics writers go through dlo::writeAtomically: they throw the OutputError naming `path`.
void exportTrajectoryTum(const SlamMap& map, const std::string& path) {
  metrics::writeTumTrajectory(path, frameTrajectory(map));
}

void exportTrajectoryKitti(const SlamMap& map, const std::string& path) {
  metrics::writeKittiTrajectory(path, frameTrajectory(map));
}

}  // namespace dlo
