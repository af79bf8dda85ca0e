#include "dlo/slam/slam_config.h"

#include "dlo/mrpt/dlo_config.h"

namespace dlo {

namespace {

std::vector<ParamField<SlamParams>> fields() {
  using S = SlamParams;
  using O = OdometryParams;
  using L = LoopParams;
  std::vector<ParamField<S>> table;
  for (const ParamField<DloParams>& f : dloParamFields()) {
    table.push_back(liftField(f, &S::registration));
  }
  const std::vector<ParamField<S>> own = {
      paramField("odometry", "reference", &S::odometry, &O::reference,
                 "what each scan is registered against: 0 = previous scan (the paper's "
                 "frame-to-frame), 1 = last keyframe, 2 = local map of recent keyframes, 3 = "
                 "world-fixed local height map of the last registered scans, updated every scan"),
      paramField("odometry", "levelling", &S::odometry, &O::levelling,
                 "1: z, roll and pitch of each scan measured from its ground laid on the "
                 "reference's ground, x, y and yaw registered by solver.dof = 3 (a 3D "
                 "trajectory); 0: z, roll and pitch kept as predicted (the paper's planar "
                 "3-DoF); ignored with solver.dof = 6, which solves all six jointly"),
      paramField("odometry", "local_map_keyframes", &S::odometry, &O::local_map_keyframes,
                 "keyframes fused into the local map (reference = 2)"),
      paramField("odometry", "local_map_scans", &S::odometry, &O::local_map_scans,
                 "registered scans in the local height map (reference = 3)"),
      paramField("odometry", "local_map_spacing", &S::odometry, &O::local_map_spacing,
                 "metres; a registered scan joins the local height map (reference = 3) only "
                 "this far from the last scan that joined it, so that the map's scans are "
                 "spread out and the pattern of rings that travels with a sparse sensor "
                 "cancels out; 0: every scan joins"),
      paramField("odometry", "max_prior_deviation", &S::odometry, &O::max_prior_deviation,
                 "metres; a registration farther than this from the constant-velocity "
                 "prediction (rotations counted at solver.rotation_scale) is decided by the "
                 "scan: deskewed with the motion it measured and registered from other starts, "
                 "the best fit wins if it beats the prediction's by a margin growing with its "
                 "distance from it (README); the bound grows by as much with each consecutive "
                 "scan where the prediction was kept (a quarter as much for rotations); 0: off"),
      paramField("odometry", "max_acceleration", &S::odometry, &O::max_acceleration,
                 "m/s^2; the velocity carried to the next scan changes by at most this per "
                 "second, unless the scan disagreed with the prediction and its registration "
                 "halved the prediction's cost; 0: no limit"),
      paramField("odometry", "max_yaw_acceleration", &S::odometry, &O::max_yaw_acceleration,
                 "deg/s^2; likewise for the yaw rate; 0: no limit"),
      paramField("odometry", "max_rejected_scans", &S::odometry, &O::max_rejected_scans,
                 "consecutive scans where the prediction was kept after which registrations are "
                 "believed again"),
      paramField("odometry", "max_speed", &S::odometry, &O::max_speed,
                 "m/s; the fastest the vehicle is expected to move: until the velocity along a "
                 "direction is measured, a registration that cannot observe that direction "
                 "searches for structure along it up to this speed; 0: never search"),
      paramField("odometry", "keyframe_distance", &S::odometry, &O::keyframe_distance,
                 "metres travelled since the last keyframe that make a new one"),
      paramField("odometry", "keyframe_angle", &S::odometry, &O::keyframe_angle,
                 "degrees turned since the last keyframe that make a new one"),
      paramField("odometry", "keyframe_max_rms", &S::odometry, &O::keyframe_max_rms,
                 "0 (off) or the registration RMS height error (m) above which the scan "
                 "becomes a keyframe (reference 1 or 2 only: their reference is made of "
                 "keyframes)"),
      paramField("odometry", "keyframe_rms_ratio", &S::odometry, &O::keyframe_rms_ratio,
                 "0 (off) or >= 1: a fit above keyframe_max_rms makes a keyframe only if it is "
                 "also this many times worse than the first fits against the last 5 keyframes"),
      paramField("odometry", "keyframe_voxel", &S::odometry, &O::keyframe_voxel,
                 "metres; decimation of keyframe clouds for the local map"),
      paramField("odometry", "map_voxel", &S::odometry, &O::map_voxel,
                 "metres; decimation of keyframe clouds kept for loop closure and the map"),
      paramField("odometry", "map_range", &S::odometry, &O::map_range,
                 "metres; keyframe points farther than this from the vehicle are not kept"),
      paramField(
          "odometry", "deskew", &S::odometry, &O::deskew,
          "1: undo motion distortion (with the points' times, measured or estimated); 0: off"),
      paramField("odometry", "estimate_times", &S::odometry, &O::estimate_times,
                 "1: scans without per-point times (KITTI .bin, PLY, point-cloud observations) "
                 "get them estimated from the points' azimuths and are deskewed; 0: used as "
                 "they are"),
      paramField("odometry", "sweep_period", &S::odometry, &O::sweep_period,
                 "seconds per revolution of the sensor (estimated times)"),
      paramField("odometry", "sweep_direction", &S::odometry, &O::sweep_direction,
                 "-1: the sensor spins clockwise seen from above (Velodyne, Ouster, Hesai); 1: "
                 "counter-clockwise; used when the point order does not reveal it"),
      paramField("odometry", "sweep_start_azimuth", &S::odometry, &O::sweep_start_azimuth,
                 "degrees counter-clockwise from forward where a sweep begins (KITTI: 180); "
                 "used when the point order does not reveal it"),
      paramField("odometry", "sweep_stamp", &S::odometry, &O::sweep_stamp,
                 "where in its sweep a scan without per-point times is stamped: 0 first point, "
                 "0.5 middle (KITTI), 1 last point"),
      paramField("odometry", "resident_keyframes", &S::odometry, &O::resident_keyframes,
                 "keyframe clouds kept in memory; older ones wait in a temporary file until "
                 "loop closure or export reads them (flat memory on long runs); 0: all in memory"),
      paramField("loop", "enabled", &S::loop, &L::enabled, "1: search and close loops; 0: off"),
      paramField("loop", "search_radius", &S::loop, &L::search_radius,
                 "metres between keyframe positions for a loop candidate"),
      paramField("loop", "min_path", &S::loop, &L::min_path,
                 "metres travelled between the two keyframes of a candidate, at least"),
      paramField("loop", "retry_distance", &S::loop, &L::retry_distance,
                 "metres travelled after a search that closed no loop before the next one; 0: "
                 "search at every keyframe"),
      paramField("loop", "resolution", &S::loop, &L::resolution,
                 "metres per cell of the verification grid"),
      paramField("loop", "window", &S::loop, &L::window, "metres; side of the verification grid"),
      paramField("loop", "max_rms", &S::loop, &L::max_rms,
                 "verification RMS height error (m) above which a candidate is rejected"),
      paramField("loop", "min_inliers", &S::loop, &L::min_inliers,
                 "fraction of the selected cells that must keep a residual"),
      paramField("loop", "max_correction", &S::loop, &L::max_correction,
                 "metres between the guess and the verified pose, at most"),
      paramField("loop", "max_disagreement", &S::loop, &L::max_disagreement,
                 "metres between two verifications started from different guesses, at most"),
      paramField("loop", "min_sigma_xy", &S::loop, &L::min_sigma_xy,
                 "metres; floor of the standard deviations of graph edges (x, y, z)"),
      paramField("loop", "min_sigma_angle", &S::loop, &L::min_sigma_angle,
                 "degrees; floor of the standard deviations of graph edges (angles)"),
  };
  table.insert(table.end(), own.begin(), own.end());
  return table;
}

}  // namespace

const ParamTable<SlamParams>& slamParamTable() {
  static const ParamTable<SlamParams> t(fields(), [](const SlamParams& p) { return p.validate(); });
  return t;
}

SlamParams loadSlamParamsFile(const std::string& path, const SlamParams& defaults) {
  return slamParamTable().loadFile(path, "", defaults);
}

void applySlamParamOverrides(SlamParams& params, const std::vector<std::string>& assignments) {
  slamParamTable().applyOverrides(params, assignments);
}

std::string slamParamsToIni(const SlamParams& params) {
  return slamParamTable().toIni(params, "");
}

}  // namespace dlo
