#include "dlo/export/simple_map_export.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include "dlo/export/height_map_export.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

mrpt::maps::CSimpleMap toSimpleMap(const SlamMap& map) {
  mrpt::maps::CSimpleMap out;
  WeightedCloud buffer;
  for (size_t i = 0; i < map.keyframes.size(); ++i) {
    const Keyframe& kf = map.keyframes[i];
    const WeightedCloud& cloud = map.keyframeCloud(i, buffer);
    auto points = mrpt::maps::CSimplePointsMap::Create();
    points->reserve(cloud.size());
    for (const WeightedPoint& wp : cloud) points->insertPoint(wp.p.x(), wp.p.y(), wp.p.z());
    auto obs = mrpt::obs::CObservationPointCloud::Create();
    obs->sensorLabel = "LIDAR";
    obs->timestamp = mrpt::Clock::fromDouble(kf.time);
    obs->sensorPose = mrpt::poses::CPose3D();
    obs->pointcloud = points;
    auto frame = mrpt::obs::CSensoryFrame::Create();
    frame->insert(obs);
    auto pose = mrpt::poses::CPose3DPDFGaussian::Create();
    pose->mean = toCPose3D(kf.pose);
    pose->cov.setZero();
    out.insert(pose, frame);
  }
  return out;
}

void exportSimpleMap(const SlamMap& map, const std::string& path) {
  // What CSimpleMap::saveToFile() writes, a gzip stream, but stored rather than deflated:
  // keyframe clouds of float coordinates shrink by only a tenth even at zlib's fastest level,
  // which took most of the export's time (docs/benchmarks.md). MRPT reads either alike.
  exportSerializedGz(toSimpleMap(map), path, 0);
}

}  // namespace dlo
