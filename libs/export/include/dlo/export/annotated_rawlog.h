/// \file annotated_rawlog.h
/// \brief The input scans written back as an MRPT rawlog with the estimated motion, for MRPT's
/// own tools (RawLogViewer, rawlog-edit, pf-localization, the 2D SLAM and navigation apps).
#pragma once

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <Eigen/Geometry>
#include <string>

#include "dlo/core/point_cloud.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/export/occupancy_grid_export.h"
#include "dlo/mrpt/rawlog_writer.h"
#include "dlo/mrpt/scan_source.h"

namespace dlo {

/// The horizontal 2D laser scan emulated from a 3D scan: what a scanner at the vehicle's origin
/// would see of the obstacles that map.gridmap marks (the same rule: a point rising between
/// OccupancyGridOptions::obstacle_height and max_height above the lowest point within
/// ground_radius).
struct Emulated2DScanOptions {
  /// Which points are obstacles (resolution, heights and ground radius); margin is not used.
  OccupancyGridOptions obstacles;
  /// Rays over the full circle, counter-clockwise from behind (MRPT's `rightToLeft`): 720 is one
  /// every half degree.
  int rays = 720;
  /// Rays reach this far (metres); a ray that meets no obstacle within it is invalid.
  double max_range = 60.0;
  /// Height of the emulated scanner above the vehicle origin (metres; only its sensorPose).
  double height = 0.0;
  /// The observation's sensorLabel.
  std::string sensor_label = "DLO_2D_SCAN";
};

/// The emulated 2D scan of `vehicle_points` (a scan in the vehicle frame), stamped `stamp`. Ray
/// i points at angle -pi + (i + 0.5) 2 pi / rays from the vehicle's x axis (aperture
/// 2 pi (rays - 1) / rays, so that no two rays coincide); its range is the horizontal distance
/// to the nearest obstacle point within half a ray's width.
/// \throws std::invalid_argument if rays < 2 or max_range is not positive.
mrpt::obs::CObservation2DRangeScan::Ptr emulate2DScan(const PointCloud& vehicle_points,
                                                      mrpt::Clock::time_point stamp,
                                                      const Emulated2DScanOptions& options = {});

/// Writes scans and their estimated poses as a rawlog in the (CActionCollection,
/// CSensoryFrame) layout that MRPT's tools replay. Each scan becomes:
/// - an action collection with the motion since the previous scan (zero for the first) as a
///   CActionRobotMovement3D (poseChange: the 6-D motion, `covariance` as given) and a
///   CActionRobotMovement2D (its planar part, with MRPT's default Gaussian odometry noise model,
///   which pf-localization samples from); both are stamped with the scan and marked as
///   odometry (emOdometry: MRPT's tools may apply their own motion model to the increment);
/// - a sensory frame with the scan's own observation as the input stored it (or, for inputs
///   that are not MRPT observations, a CObservationPointCloud of its points in the vehicle
///   frame, as measured) and the 2D scan emulated from its deskewed points (emulate2DScan()).
///
/// Streaming (one scan in memory) and atomic as RawlogWriter: nothing appears at `path` until
/// commit().
class AnnotatedRawlogWriter {
 public:
  /// \throws OutputError naming the file if it cannot be created.
  explicit AnnotatedRawlogWriter(const std::string& path,
                                 const Emulated2DScanOptions& options = {});

  /// Appends `scan` at `pose` (its world pose; the motion written is the change since the pose
  /// of the previous call). `deskewed`: the scan's points moved to where they were at the
  /// scan's time (dlo::deskew), from which the 2D scan is emulated (a sweep distorted by the
  /// motion would place the obstacles where the vehicle was half a sweep earlier); scan.points
  /// where the motion within the sweep is unknown. `covariance`: of the motion as a twist (x,
  /// y, z and the rotation vector, as dlo::logSE3), converted to MRPT's (x, y, z, yaw, pitch,
  /// roll).
  void write(const TimedScan& scan, const Eigen::Isometry3d& pose, const PointCloud& deskewed,
             const Matrix6d& covariance = defaultMotionCovariance());

  /// Scans written so far.
  size_t count() const { return scans_; }

  /// Closes the file and renames it into place. \throws OutputError if that fails.
  void commit() { writer_.commit(); }

  /// Where the entries written so far are kept if commit() is never called.
  std::string partialPath() const { return writer_.partialPath(); }

  /// What write() uses when no covariance is known: 5 cm and 0.5 degrees (one sigma) per axis.
  static Matrix6d defaultMotionCovariance();

 private:
  RawlogWriter writer_;
  Emulated2DScanOptions options_;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  size_t scans_ = 0;
};

}  // namespace dlo
