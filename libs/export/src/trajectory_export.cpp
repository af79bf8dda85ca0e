#include "dlo/export/trajectory_export.h"

#include "dlo/files/atomic_file.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo {

metrics::Trajectory frameTrajectory(const SlamMap& map) {
  metrics::Trajectory t;
  for (size_t i = 0; i < map.frames.size(); ++i) t.push_back(map.frames[i].time, map.framePose(i));
  return t;
}

// The metrics writers are atomic themselves and name `path`; only the exception type changes.
void exportTrajectoryTum(const SlamMap& map, const std::string& path) {
  try {
    metrics::writeTumTrajectory(path, frameTrajectory(map));
  } catch (const std::runtime_error& e) {
    throw OutputError(e.what());
  }
}

void exportTrajectoryKitti(const SlamMap& map, const std::string& path) {
  try {
    metrics::writeKittiTrajectory(path, frameTrajectory(map));
  } catch (const std::runtime_error& e) {
    throw OutputError(e.what());
  }
}

}  // namespace dlo
