#include "dlo/export/annotated_rawlog.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "dlo/core/units.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {

mrpt::obs::CObservation2DRangeScan::Ptr emulate2DScan(const PointCloud& vehicle_points,
                                                      mrpt::Clock::time_point stamp,
                                                      const Emulated2DScanOptions& options) {
  if (options.rays < 2 || !(options.max_range > 0.0)) {
    throw std::invalid_argument(
        "Emulated2DScanOptions: rays must be 2 or more, max_range positive");
  }
  // The obstacle rule of the occupancy grid, on the points within reach (and the ground radius
  // beyond, so that the local ground of the farthest obstacles is seen).
  const double reach = options.max_range + options.obstacles.ground_radius;
  const float reach2 = static_cast<float>(reach * reach);
  PointCloud near;
  near.reserve(vehicle_points.size());
  for (const Eigen::Vector3f& p : vehicle_points) {
    if (p.head<2>().squaredNorm() <= reach2) near.push_back(p);
  }
  OccupancyGridOptions grid = options.obstacles;
  grid.margin = 0.0;
  OccupancyGridAccumulator obstacles(grid);
  const WeightedCloud cloud = unitWeights(near);
  obstacles.extend(cloud);
  obstacles.ground(cloud);

  const int n = options.rays;
  const double step = 2.0 * M_PI / n;
  const float far = static_cast<float>(options.max_range);
  std::vector<float> range(n, far);
  const float low = static_cast<float>(grid.obstacle_height);
  const float high = static_cast<float>(grid.max_height);
  for (const Eigen::Vector3f& p : near) {
    const float r = p.head<2>().norm();
    if (!(r < far)) continue;
    const float above = obstacles.heightAboveGround(p.x(), p.y(), p.z());
    if (!(above > low && above <= high)) continue;
    // Ray i covers angles [-pi + i step, -pi + (i + 1) step).
    const double a = std::atan2(static_cast<double>(p.y()), static_cast<double>(p.x()));
    int i = static_cast<int>(std::floor((a + M_PI) / step));
    i = std::min(std::max(i, 0), n - 1);
    range[i] = std::min(range[i], r);
  }

  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  scan->timestamp = stamp;
  scan->sensorLabel = options.sensor_label;
  scan->aperture = static_cast<float>(2.0 * M_PI * (n - 1) / n);
  scan->rightToLeft = true;
  scan->maxRange = far;
  scan->stdError = static_cast<float>(grid.resolution);
  scan->sensorPose = mrpt::poses::CPose3D(0.0, 0.0, options.height, 0.0, 0.0, 0.0);
  scan->resizeScan(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    scan->setScanRange(static_cast<size_t>(i), range[i]);
    scan->setScanRangeValidity(static_cast<size_t>(i), range[i] < far);
  }
  return scan;
}

AnnotatedRawlogWriter::AnnotatedRawlogWriter(const std::string& path,
                                             const Emulated2DScanOptions& options)
    : writer_(path), options_(options) {}

Matrix6d AnnotatedRawlogWriter::defaultMotionCovariance() {
  Vector6d sigma;
  sigma << 0.05, 0.05, 0.05, 0.5 * kDeg, 0.5 * kDeg, 0.5 * kDeg;
  return sigma.cwiseAbs2().asDiagonal();
}

void AnnotatedRawlogWriter::write(const TimedScan& scan, const Eigen::Isometry3d& pose,
                                  const PointCloud& deskewed, const Matrix6d& covariance) {
  const Eigen::Isometry3d motion =
      scans_ == 0 ? Eigen::Isometry3d::Identity() : Eigen::Isometry3d(last_pose_.inverse() * pose);
  const mrpt::poses::CPose3D change = toCPose3D(motion);

  mrpt::obs::CActionCollection actions;
  mrpt::obs::CActionRobotMovement3D moved3d;
  moved3d.timestamp = scan.timestamp;
  moved3d.estimationMethod = mrpt::obs::CActionRobotMovement3D::emOdometry;
  moved3d.rawOdometryIncrementReading = change;
  mrpt::math::CMatrixDouble66 cov;
  const Matrix6d c = twistCovarianceToXYZYPR(motion, covariance);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) cov(i, j) = c(i, j);
  moved3d.poseChange = mrpt::poses::CPose3DPDFGaussian(change, cov);
  actions.insert(moved3d);

  mrpt::obs::CActionRobotMovement2D moved2d;
  moved2d.computeFromOdometry(mrpt::poses::CPose2D(change),
                              mrpt::obs::CActionRobotMovement2D::TMotionModelOptions());
  moved2d.timestamp = scan.timestamp;
  actions.insert(moved2d);

  mrpt::obs::CSensoryFrame frame;
  if (scan.observation) {
    frame.insert(scan.observation);
  } else {
    auto cloud = mrpt::obs::CObservationPointCloud::Create();
    auto points = mrpt::maps::CSimplePointsMap::Create();
    points->reserve(scan.points.size());
    for (const Eigen::Vector3f& p : scan.points) points->insertPointFast(p.x(), p.y(), p.z());
    cloud->pointcloud = points;
    cloud->timestamp = scan.timestamp;
    cloud->sensorLabel = scan.sensor_label.empty() ? "LIDAR" : scan.sensor_label;
    frame.insert(cloud);
  }
  frame.insert(emulate2DScan(deskewed, scan.timestamp, options_));

  writer_.write(actions);
  writer_.write(frame);
  last_pose_ = pose;
  ++scans_;
}

}  // namespace dlo
