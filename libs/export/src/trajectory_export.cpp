#include "dlo/export/trajectory_export.h"

#include "dlo/export/atomic_file.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo {

metrics::Trajectory frameTrajectory(const SlamMap& map) {
  metrics::Trajectory t;
  for (size_t i = 0; i < map.frames.size(); ++i) t.push_back(map.frames[i].time, map.framePose(i));
  return t;
}

void exportTrajectoryTum(const SlamMap& map, const std::string& path) {
  const metrics::Trajectory t = frameTrajectory(map);
  writeAtomically(path, [&](const std::string& temp) { metrics::writeTumTrajectory(temp, t); });
}

void exportTrajectoryKitti(const SlamMap& map, const std::string& path) {
  const metrics::Trajectory t = frameTrajectory(map);
  writeAtomically(path, [&](const std::string& temp) { metrics::writeKittiTrajectory(temp, t); });
}

}  // namespace dlo
