/// \file trajectory_export.h
/// \brief The trajectory of a SLAM run as TUM and KITTI files.
#pragma once

#include <string>

#include "dlo/metrics/trajectory.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// One pose per processed frame: SlamMap::framePose(i) stamped with frames[i].time. The world
/// frame is the map's (the first scan's vehicle frame), so the first pose is the identity when
/// the map's first frame is.
metrics::Trajectory frameTrajectory(const SlamMap& map);

/// Writes frameTrajectory() as a TUM file ("t x y z qx qy qz qw"), atomically.
/// \throws OutputError naming `path`.
void exportTrajectoryTum(const SlamMap& map, const std::string& path);

/// Writes frameTrajectory() as a KITTI pose file (3x4 row-major per line, no times), atomically.
/// \throws OutputError naming `path`.
void exportTrajectoryKitti(const SlamMap& map, const std::string& path);

}  // namespace dlo
