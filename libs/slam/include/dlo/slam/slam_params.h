/// \file slam_params.h
/// \brief Parameters of the odometry, keyframes and loop closure (INI sections [odometry] and
/// [loop]); the registration itself is configured by dlo::DloParams.
#pragma once

#include <string>

#include "dlo/core/dlo_params.h"

namespace dlo {

/// What each scan is registered against (odometry.reference; the INI names in quotes).
enum class Reference {
  kPreviousScan = 0,  ///< "previous": the previous scan (the paper's frame-to-frame)
  kKeyframe = 1,      ///< "keyframe": the last keyframe
  kKeyframeMap = 2,   ///< "keyframe_map": a height map fused from the last local_map_keyframes
  /// "scan_map": a world-fixed local height map of the last local_map_scans registered scans,
  /// updated every scan (dlo::LocalHeightMap; what sparse sensors need:
  /// config/sensors/sparse.ini).
  kScanMap = 3,
};

/// Odometry and keyframes (INI section [odometry]).
struct OdometryParams {
  /// What each scan is registered against.
  Reference reference = Reference::kKeyframeMap;
  /// true: z, roll and pitch of every scan are measured from its ground (dlo::fitGroundSurface)
  /// laid on the reference's ground at the registered x, y and heading (dlo::alignToGround),
  /// with solver.dof = 3 registering x, y and yaw: a 3D trajectory. false: they stay as
  /// predicted, the paper's planar 3-DoF odometry. solver.dof = 6 solves all six jointly and
  /// ignores this.
  bool levelling = true;
  /// true: heights above what the sensor sees from every range on the registration grid are
  /// left out (grid.max_z lowered to the sensor's height plus ceiling_above_sensor, or to what
  /// its highest beam reaches at the grid's edge where that is lower, both read off the first
  /// scan: dlo::applyVisibilityCeiling). A wall then has the same mean height from every range
  /// within the grid, instead of growing with the distance as the sensor's upper beams climb it,
  /// which pulls registrations towards zero motion. Applied by dlo-slam, which knows the sensor's
  /// pose; dlo-localize keeps whole heights, as the map it reads does. Off in the sparse profile
  /// (config/sensors/sparse.ini): sparse scans have too few cells to lose the walls' upper parts.
  bool visibility_ceiling = true;
  /// Metres: with visibility_ceiling, the band kept above the sensor's own height. A beam at or
  /// above the horizontal sees a wall up to the sensor's height from any range, and above it only
  /// from far enough away (an Ouster-like sensor's +22.5 deg beam: from 5 m up to 2 m above
  /// itself, from 20 m up to 8 m). The band trades what near walls lose above the sensor
  /// against ground that rises ahead over a crest; 0.7 m is what an HDL-64's +2 deg beam reaches
  /// at the dense grid's edge. Measurements: docs/benchmarks.md.
  double ceiling_above_sensor = 0.7;
  /// Keyframes fused into the local map (reference = keyframe_map), at most. Each keyframe's
  /// pattern of rings travels with the sensor and pulls a scan towards where that keyframe was
  /// taken; keyframes taken close together (by angle, turning on the spot) add such patterns at
  /// nearly one place, and more of them dilute each one.
  int local_map_keyframes = 8;
  /// Metres: a keyframe farther than this from the newest one leaves the local map (reference =
  /// keyframe_map) before local_map_keyframes newer ones replace it: older keyframes carry
  /// more of the odometry's drift, worst along what the scans could not observe (an open
  /// road's length). 0: no limit.
  double local_map_extent = 12.0;
  /// Registered scans in the local height map (reference = scan_map). Fewer scans let a wrongly
  /// placed one leave the map sooner; enough of them cover the ground between a sparse
  /// sensor's rings (measurements: docs/benchmarks.md).
  int local_map_scans = 15;
  /// Metres: a registered scan joins the scan map (reference = scan_map) only this far from the
  /// last scan that joined it, and a keyframe closer than this to the keyframe map's newest
  /// (reference = keyframe_map; a turn on the spot makes one every keyframe_angle) replaces it.
  /// Each scan's pattern of rings and holes travels with the sensor and pulls a registration
  /// towards where that scan was taken; views a few centimetres apart (a robot at 1.5 m/s, or
  /// turning on the spot) add the same pattern again, spread over metres they cancel out. 0:
  /// every registered scan or keyframe joins.
  double local_map_spacing = 0.6;
  /// Metres: a registration farther than this from the constant-velocity prediction (rotations
  /// counted as their displacement at solver.rotation_scale) is rejected, the prediction kept
  /// and the scan flagged degenerate; the bound grows by as much with every consecutive
  /// rejection (the prediction ages), a quarter as much for rotations; 0 disables.
  double max_prior_deviation = 0.3;
  /// true: a registration that moved from the prediction by more than a quarter of
  /// max_prior_deviation yet fits the scan worse than the prediction (the mean robust cost of its
  /// cells) is decided by the scan as a registration beyond max_prior_deviation is: registered
  /// from other starts, the best fit believed if it beats the prediction's. Gauss-Newton on
  /// smoothed gradients does not descend the cost, and on sparse scans it can cycle to an end
  /// degrees off on a straight. The sparse profile sets it; dense scans braking hard fit the
  /// prediction better than the registrations that follow the braking, which it would then
  /// overrule (measurements: docs/benchmarks.md).
  bool recheck_worse_fits = false;
  /// m/s^2: the speed carried to the next scan changes by at most this per second (a car
  /// brakes at up to about 10); 0: no limit.
  double max_acceleration = 10.0;
  /// deg/s^2: likewise for the yaw rate (entering a 10 m radius turn at 8 m/s takes about 50),
  /// unless the scan disagreed with the prediction and its registration halved the
  /// prediction's cost (OdometryStep::convincing: a robot that turns on the spot starts and
  /// stops its turn within a scan); 0: no limit.
  double max_yaw_acceleration = 120.0;
  /// Seconds: the time constant with which a yaw rate that no scan measures returns to zero.
  /// The velocity carries a turn into the next scans; where registrations cannot observe the
  /// yaw (an open road, a covered sensor) or observe it weakly, the part of the rate they do
  /// not measure decays by exp(-dt / yaw_rate_decay) per interval instead of being carried
  /// at full rate: a vehicle's turns end. A registration that observes the yaw sets the rate
  /// as before. 0: the rate is carried unchanged (constant velocity).
  double yaw_rate_decay = 3.0;
  /// Consecutive rejected scans after which registrations are believed again: by then the
  /// prediction is the more likely culprit.
  int max_rejected_scans = 5;
  /// m/s: the fastest the vehicle is expected to move. Until registrations have measured the
  /// velocity along a direction (a drive that starts at speed on a road that constrains
  /// nothing along it), the prediction is that uncertain along it, and a registration that
  /// cannot observe that direction searches up to this speed along it for structure that can
  /// (LidarOdometry::searchUnobserved). 0: never search.
  double max_speed = 40.0;
  /// deg/s: the fastest the vehicle is expected to turn. A registration converges within the
  /// basin of the coarsest level around its start, which a robot that begins to turn on the
  /// spot at 150 deg/s leaves within one sweep: each scan's fit is compared at the coarsest
  /// level over headings that keep the yaw rate within this, and where one fits better
  /// the scan is registered from there too (LidarOdometry::searchTurn). 0: never search.
  double max_yaw_rate = 180.0;
  double keyframe_distance = 2.0;  ///< metres travelled since the last keyframe: new keyframe
  double keyframe_angle = 10.0;    ///< degrees turned since the last keyframe: new keyframe
  /// 0 (off), or the registration RMS height error (m) above which a scan becomes a keyframe,
  /// with reference keyframe or keyframe_map (whose reference is made of keyframes) only, and where
  /// keyframe_rms_ratio is set, only if the fit is also that many times worse than fresh
  /// keyframes give. Off by default: the height error is dominated by the edges of walls and
  /// canopies, above any fixed bound on real and 128-beam scans even right after a keyframe, and
  /// the keyframes it adds at walking speed chain small registrations whose errors add up
  /// (docs/benchmarks.md).
  double keyframe_max_rms = 0.0;
  /// 0 (off), or at least 1: a fit above keyframe_max_rms makes a keyframe only if it is also
  /// this many times worse than the median of the first fits against the last 5 new keyframes
  /// (what a new keyframe could not improve on, such as sensor noise or vegetation, then makes
  /// none). Fewer keyframes where every fit is above the bound (real and 128-beam scans), at
  /// some cost in drift; docs/benchmarks.md.
  double keyframe_rms_ratio = 0.0;
  /// metres; decimation of keyframe clouds for the local map; 0 keeps every point (at 0.05 m an
  /// HDL-64 sweep keeps 91k of 117k points and the local map rasterised four such clouds per
  /// keyframe, hence 0.1 m, README; every point let the simulated open field of the
  /// degenerate-scene tests leave its street with a 1.8 deg yaw error against 0.04 deg)
  double keyframe_voxel = 0.1;
  double map_voxel = 0.2;   ///< metres; decimation of keyframe clouds kept for the map
  double map_range = 40.0;  ///< metres; keyframe points farther than this are not kept
  bool deskew = true;       ///< undo motion distortion (measured or estimated times)
  /// true: a scan without per-point times (KITTI .bin, PLY, CObservationPointCloud) gets them
  /// estimated from the points' azimuths (dlo::estimateSweepTimes) and is deskewed like the
  /// others; false: such scans are used as they are.
  bool estimate_times = true;
  /// Seconds per revolution of the sensor (estimate_times); 0: read off the scans' timestamps
  /// (their mean interval, dropped scans and gaps left out: dlo::SweepPeriodEstimate), 0.1 s
  /// until the second scan.
  double sweep_period = 0.0;
  /// Spin direction, -1 clockwise seen from above (Velodyne, Ouster, Hesai) or +1; used when
  /// the point order does not reveal it (estimate_times).
  int sweep_direction = -1;
  /// Degrees counter-clockwise from forward where a sweep begins (KITTI: 180, behind); used
  /// when the point order does not reveal it (estimate_times).
  double sweep_start_azimuth = 180.0;
  /// Fraction of the sweep at which a scan without per-point times is stamped: 0 its first
  /// point, 0.5 its middle (KITTI), 1 its end (estimate_times).
  double sweep_stamp = 0.5;
  /// Keyframe clouds kept in memory; older ones move to a temporary file and are read back
  /// when a loop closure or the export needs them, so memory stays flat on long runs. 0: all
  /// stay in memory.
  int resident_keyframes = 50;
};

/// Loop closure (INI section [loop]).
struct LoopParams {
  bool enabled = true;          ///< false disables loop closure
  double search_radius = 12.0;  ///< metres between keyframe positions to be a candidate
  double min_path = 40.0;       ///< metres travelled between the two keyframes, at least
  /// Metres travelled after a lattice search that closed no loop before the next one: the same
  /// place seen a metre later rarely verifies where it did not; 0 searches at every keyframe.
  double retry_distance = 2.0;
  double resolution = 0.2;      ///< metres per cell of the verification grid
  double window = 60.0;         ///< metres; side of the verification grid
  double max_rms = 0.45;        ///< verification RMS height error above this (m): rejected
  double min_inliers = 0.5;     ///< fraction of selected cells with a residual, at least
  double max_correction = 6.0;  ///< metres between guess and verified pose, at most
  /// metres: with `confirm`, the two loops must put the vehicle within this of each other
  double max_disagreement = 0.75;
  double min_sigma_xy = 0.05;    ///< metres; floor of edge standard deviations (x, y, z)
  double min_sigma_angle = 0.2;  ///< degrees; floor of edge standard deviations (angles)
  /// Keyframes whose clouds make each side of a verification: the keyframe and its neighbours
  /// along the drive (centred on it where they exist), put in its frame by their poses. 1: the
  /// keyframe alone. A sparse sensor's keyframes leave the ground between their rings empty, and
  /// two of them taken metres apart rarely measure the same cells.
  int submap_keyframes = 1;
  /// true: the first loop of a revisit (found by the lattice search) is added only once a later
  /// keyframe's lattice search finds a loop that puts the vehicle in the same basin (within
  /// max_disagreement and 2.5 deg, through the graph's poses between them); false: one
  /// verification suffices.
  bool confirm = false;
};

/// Everything dlo-slam is configured with.
struct SlamParams {
  /// The pipeline's registration puts the cells of its two finest levels at their points'
  /// centroids (selection.centroid_levels = 2, the dense profile): against the keyframe map 8-13 %
  /// less drift on the simulated dense drives than at the cells' centres (docs/benchmarks.md).
  /// DloParams alone keeps the paper's cell centres (dlo-register, CDirectHeightAligner).
  /// Its grid spans 60 m (600 x 600 cells of 0.1 m) rather than the paper's 40 m: along a street
  /// most of what constrains the motion along it lies beyond 20 m, and registrations over 40 m
  /// fall short of the motion (docs/benchmarks.md). DloParams alone keeps the paper's 400 cells.
  SlamParams() {
    registration.selection.centroid_levels = 2;
    registration.grid.cols = registration.grid.rows = 600;
  }

  DloParams registration;   ///< [grid] [selection] [solver]
  OdometryParams odometry;  ///< [odometry]
  LoopParams loop;          ///< [loop]

  /// Empty when acceptable, otherwise one sentence naming section.key and the accepted range.
  std::string validate() const;
};

}  // namespace dlo
