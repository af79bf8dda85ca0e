#include "dlo/slam/slam_params.h"

#include "dlo/core/range_message.h"

namespace dlo {

std::string SlamParams::validate() const {
  if (std::string e = registration.validate(); !e.empty()) return e;
  const OdometryParams& o = odometry;
  // An enum set from code can hold any int; the INI names cannot.
  const int reference = static_cast<int>(o.reference);
  if (reference < 0 || reference > 3)
    return outOfRange("odometry.reference", reference,
                      "previous, keyframe, keyframe_map or scan_map");
  if (o.local_map_keyframes < 1 || o.local_map_keyframes > 50)
    return outOfRange("odometry.local_map_keyframes", o.local_map_keyframes, "1..50");
  if (!(o.local_map_extent >= 0.0 && o.local_map_extent <= 1000.0))
    return outOfRange("odometry.local_map_extent", o.local_map_extent, "0..1000");
  if (o.local_map_scans < 1 || o.local_map_scans > 100)
    return outOfRange("odometry.local_map_scans", o.local_map_scans, "1..100");
  if (!(o.local_map_spacing >= 0.0 && o.local_map_spacing <= 10.0))
    return outOfRange("odometry.local_map_spacing", o.local_map_spacing,
                      "[0, 10] metres (0: every scan)");
  if (!(o.max_prior_deviation >= 0.0))
    return outOfRange("odometry.max_prior_deviation", o.max_prior_deviation,
                      ">= 0 metres (0: off)");
  if (!(o.max_acceleration >= 0.0))
    return outOfRange("odometry.max_acceleration", o.max_acceleration, ">= 0 m/s^2 (0: off)");
  if (!(o.max_yaw_acceleration >= 0.0))
    return outOfRange("odometry.max_yaw_acceleration", o.max_yaw_acceleration,
                      ">= 0 deg/s^2 (0: off)");
  if (!(o.yaw_rate_decay >= 0.0))
    return outOfRange("odometry.yaw_rate_decay", o.yaw_rate_decay, ">= 0 seconds (0: off)");
  if (!(o.max_speed >= 0.0 && o.max_speed <= 200.0))
    return outOfRange("odometry.max_speed", o.max_speed, "[0, 200] m/s (0: never search)");
  if (!(o.max_yaw_rate >= 0.0 && o.max_yaw_rate <= 3600.0))
    return outOfRange("odometry.max_yaw_rate", o.max_yaw_rate, "[0, 3600] deg/s (0: never search)");
  if (!(o.max_rejected_scans >= 1))
    return outOfRange("odometry.max_rejected_scans", o.max_rejected_scans, ">= 1 scan");
  if (!(o.keyframe_distance > 0.0))
    return outOfRange("odometry.keyframe_distance", o.keyframe_distance, "a positive distance");
  if (!(o.keyframe_angle > 0.0))
    return outOfRange("odometry.keyframe_angle", o.keyframe_angle, "a positive angle in degrees");
  if (!(o.keyframe_max_rms >= 0.0))
    return outOfRange("odometry.keyframe_max_rms", o.keyframe_max_rms,
                      "0 (off) or a positive height in metres");
  if (!(o.keyframe_rms_ratio == 0.0 || o.keyframe_rms_ratio >= 1.0))
    return outOfRange("odometry.keyframe_rms_ratio", o.keyframe_rms_ratio, "0 (off) or >= 1");
  if (!(o.ceiling_above_sensor >= 0.0 && o.ceiling_above_sensor <= 10.0))
    return outOfRange("odometry.ceiling_above_sensor", o.ceiling_above_sensor, "[0, 10] metres");
  if (!(o.keyframe_voxel >= 0.0 && o.keyframe_voxel <= 1.0))
    return outOfRange("odometry.keyframe_voxel", o.keyframe_voxel,
                      "[0, 1] metres (0: no decimation)");
  if (!(o.map_voxel > 0.0 && o.map_voxel <= 5.0))
    return outOfRange("odometry.map_voxel", o.map_voxel, "(0, 5] metres");
  if (!(o.map_range > 1.0)) return outOfRange("odometry.map_range", o.map_range, "> 1 metre");
  if (!(o.sweep_period >= 0.0 && o.sweep_period <= 1.0))
    return outOfRange("odometry.sweep_period", o.sweep_period,
                      "0 (from the scans' timestamps) or (0, 1] seconds");
  if (o.sweep_direction != -1 && o.sweep_direction != 1)
    return outOfRange("odometry.sweep_direction", o.sweep_direction,
                      "-1 (clockwise) or 1 (counter-clockwise)");
  if (!(o.sweep_start_azimuth >= -360.0 && o.sweep_start_azimuth <= 360.0))
    return outOfRange("odometry.sweep_start_azimuth", o.sweep_start_azimuth, "[-360, 360] degrees");
  if (!(o.sweep_stamp >= 0.0 && o.sweep_stamp <= 1.0))
    return outOfRange("odometry.sweep_stamp", o.sweep_stamp, "[0, 1] of a sweep");
  if (!(o.resident_keyframes >= 0))
    return outOfRange("odometry.resident_keyframes", o.resident_keyframes,
                      "0 (all in memory) or more keyframes");
  const LoopParams& l = loop;
  if (!(l.search_radius > 0.0))
    return outOfRange("loop.search_radius", l.search_radius, "a positive distance");
  if (!(l.min_path >= 0.0)) return outOfRange("loop.min_path", l.min_path, ">= 0 metres");
  if (!(l.retry_distance >= 0.0))
    return outOfRange("loop.retry_distance", l.retry_distance, ">= 0 metres");
  if (!(l.resolution > 0.0 && l.resolution <= 2.0))
    return outOfRange("loop.resolution", l.resolution, "(0, 2] metres");
  if (!(l.window >= 16 * l.resolution && l.window <= 500.0))
    return outOfRange("loop.window", l.window, "16 cells of loop.resolution up to 500 metres");
  if (!(l.max_rms > 0.0)) return outOfRange("loop.max_rms", l.max_rms, "a positive height");
  if (!(l.min_inliers >= 0.0 && l.min_inliers <= 1.0))
    return outOfRange("loop.min_inliers", l.min_inliers, "[0, 1]");
  if (!(l.max_correction > 0.0))
    return outOfRange("loop.max_correction", l.max_correction, "a positive distance");
  if (!(l.max_disagreement > 0.0))
    return outOfRange("loop.max_disagreement", l.max_disagreement, "a positive distance");
  if (!(l.min_sigma_xy > 0.0))
    return outOfRange("loop.min_sigma_xy", l.min_sigma_xy, "a positive distance");
  if (!(l.min_sigma_angle > 0.0))
    return outOfRange("loop.min_sigma_angle", l.min_sigma_angle, "a positive angle");
  if (!(l.submap_keyframes >= 1 && l.submap_keyframes <= 50))
    return outOfRange("loop.submap_keyframes", l.submap_keyframes, "1 to 50 keyframes");
  return {};
}

}  // namespace dlo
