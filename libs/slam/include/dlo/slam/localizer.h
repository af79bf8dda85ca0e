/// \file localizer.h
/// \brief Localisation of a new drive on a map that dlo-slam made: a global search for the
/// first fix, then every scan registered against the prior map around its predicted pose.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/ground_surface.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/point_cloud.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/sweep_timing.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/lidar_odometry.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// The map to localise on: dlo-slam's keyframes, each a pose in the map frame and its cloud in
/// its own frame (for the global search), and its height map (what scans are registered
/// against: point counts and height sums per cell, as the odometry's grids hold them).
struct PriorMap {
  std::vector<Eigen::Isometry3d> poses;
  std::vector<WeightedCloud> clouds;
  /// Height map cells: cell (ix, iy) covers x in [x_min + ix res, x_min + (ix + 1) res) and
  /// likewise y; row-major, cols x rows.
  double x_min = 0.0, y_min = 0.0, resolution = 0.2;
  int cols = 0, rows = 0;
  std::vector<std::uint32_t> count;
  std::vector<float> sum;
  /// Per cell, where its points lie in it (HeightMapCentroids::places, 2 bytes per cell, from
  /// heightmap_centroids.bin), or empty: a map made before dlo-slam wrote them. The Localizer
  /// uses them once (centreHeights()) and keeps its map without them.
  std::vector<std::uint8_t> centroids;
  /// The heights stand at their cells' centres (centreHeights()), not at their points'
  /// centroids.
  bool heights_at_centres = false;
  size_t size() const { return poses.size(); }
};

/// Moves the mean height of every measured cell of `map` from the centroid of its points, where
/// it was measured (map.centroids), to the cell's centre, along the height map's local slope
/// (central differences of the neighbouring cells' heights, as the registration's gradients
/// take them; one-sided beside an empty cell, none between two). Compared at cell centres, a
/// mean height carries a bias wherever a cell's points lie to one side of it (a wall's face, a
/// ring crossing a kerb) that pulls a registration by centimetres. Sets map.heights_at_centres.
/// \throws std::invalid_argument if map.centroids does not hold two bytes per cell.
void centreHeights(PriorMap& map);

/// Reads a dlo-slam output folder: the keyframes of its map.simplemap, its heightmap.bin and,
/// where the folder has one, its heightmap_centroids.bin (PriorMap::centroids).
/// \throws InputError naming the file if one is missing (the centroids may be), unreadable,
/// holds nothing or (the centroids) does not match the height map.
PriorMap loadPriorMap(const std::string& slam_out_dir);

/// How the Localizer registers scans against the prior map and when it believes them. dlo-localize
/// reads them from the [localizer] section of its --config file and from --set localizer.key=value
/// (localizer_config.h); config/dlo-localize.ini documents every key.
struct LocalizerParams {
  /// Registration grid (both the scan's and the map's): cells per side, at the height map's
  /// resolution (0.2 m from dlo-slam): 60 m across.
  int cells = 300;
  /// The map reference (the height map's window around the vehicle) is rebuilt when the vehicle
  /// is this far (metres) from its centre.
  double rebuild_distance = 5.0;
  /// A registration against the map is believed (the scan is localised) when it is well
  /// conditioned, at least min_inliers of the scan's selected cells found the map, and its RMS
  /// height error is at most rms_ratio times the median of the last localised scans' (from the
  /// fix on: a wrong basin, or surroundings that changed since the map, fit worse than the drive
  /// usually does) and at most max_rms metres (the only bound for a scan tracked from --init).
  double min_inliers = 0.6;
  double rms_ratio = 1.5;
  double max_rms = 1.0;
  /// ... and it moved the pose at most this far (metres) from the prediction: from one scan to
  /// the next a dense sensor's prediction is right to centimetres, and a registration that
  /// jumps by more has found another basin. A sensor profile key: a sparse scan's fit, and so
  /// the prediction made from it, scatters by tenths of a metre (sparse.ini: 0.75).
  double max_correction = 0.5;
  /// Tracking from a prediction (or a place a search found) uses the pyramid's levels up to
  /// this cell size (metres); a search from the keyframes uses every level (up to 1.6 m). The
  /// prediction is right to centimetres, and a coarser level only adds basins to fall into.
  double tracking_basin = 0.4;
  /// After this many scans in a row that were not localised, the vehicle is lost: the next scan
  /// searches the whole map again (a kidnapping, a registration gone astray).
  int lost_after = 3;
  /// A global search is tried at most once every this many scans while lost (it registers the
  /// scan from every heading at every search_spacing along the map's keyframes).
  int search_every = 5;
  /// Global search: starts at the map's keyframes at least search_spacing metres apart, at
  /// headings search_yaw_step_deg apart. Places are compared by their cost (the mean robust
  /// height error per selected cell, a cell that found no map counted as an outlier): the best
  /// counts as found when it is believable as tracking believes a scan (min_inliers, well
  /// conditioned), its cost is at most the median place's divided by search_contrast, and
  /// every other distinct place costs at least ambiguity_ratio times more. The ambiguity ratio
  /// is what tells a place that is there from one that is not (a town the map does not hold
  /// has a second place nearly as good); the contrast only refuses scans that fit everywhere
  /// alike.
  double search_spacing = 3.0;
  double search_yaw_step_deg = 15.0;
  double search_contrast = 1.4;
  double ambiguity_ratio = 1.3;
  /// true: once the map has localised four scans in a row, the odometry stops and the localised
  /// poses' velocity predicts the next scan and deskews it; a scan it does not carry to a
  /// believable fit is registered again from an odometry started afresh on the previous scan,
  /// which then runs until four scans in a row are localised; false: the odometry runs beside
  /// every scan (two to three times the time per scan; on the simulated drives of
  /// docs/benchmarks.md, dense and sparse, no more scans localised).
  bool bridge_only = true;

  /// An empty string if every value is in range, else one sentence naming the key
  /// ("localizer.key") and the range.
  std::string validate() const;
};

/// What happened to one scan.
struct LocalizationStep {
  double time = 0.0;
  bool localised = false;  ///< the pose was measured against the map and believed
  /// Pose in the map frame: measured when localised, predicted (the last localised pose moved
  /// by the last velocity) otherwise; meaningless before the first fix.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  bool fixed = false;     ///< some scan up to this one has been localised
  bool searched = false;  ///< a global search ran on this scan
  bool found = false;     ///< ... and found the vehicle (a first fix or a re-localisation)
  double rms = 0.0;       ///< RMS height error of the registration against the map (m)
  double inliers = 0.0;   ///< fraction of the scan's selected cells that found the map
  /// How far (metres) the registration moved the pose from its prediction (the odometry's motion
  /// from the last pose); 0 for a global search.
  double correction = 0.0;
  /// In [0, 1]: inliers x (1 - rms / max_rms), 0 when not localised.
  double confidence = 0.0;
  /// The odometry ran on this scan (always, unless LocalizerParams::bridge_only).
  bool odometry = false;
  double ms = 0.0;  ///< processing time of the scan
};

/// Writes `png`: the map's keyframe clouds seen from above (grey, darker where higher), the
/// localised poses of `steps` (green), those predicted while not localised (red) and the map's
/// keyframes (blue dots). About 0.25 m per pixel, coarser for maps larger than 4000 pixels.
/// \throws OutputError naming the file if it cannot be written.
void writeLocalizationImage(const PriorMap& map, const std::vector<LocalizationStep>& steps,
                            const std::string& png);

/// Localises scans, one at a time, on a PriorMap. A LidarOdometry runs beside it: its motion
/// since the last scan predicts the pose on the map (and carries it over the scans the map does
/// not localise), and its velocity deskews the sweep. With LocalizerParams::bridge_only (the
/// default), it runs only where the map has not localised the last scans: elsewhere the
/// localised poses' velocity predicts the next pose and deskews the sweep.
/// With no initial pose the first scans search the whole map (every keyframe, every heading,
/// registered at full resolution, accepted only if one place clearly fits best); then each scan is
/// registered against the height map around its predicted pose, its z, roll and pitch from the
/// ground; where the odometry's prediction does not lead to a believable fit, the motion the last
/// localised scans measure is a second start, and the previous scan's pose (at rest) a third. A fit
/// that cannot observe one direction of the plane is believed right after a well-conditioned one
/// (its start along that direction kept). A scan that does not fit the map well keeps the
/// odometry's pose and is reported as not localised; after a few in a row the search runs again.
class Localizer {
 public:
  /// \param slam the parameters of the odometry that runs beside (and of the registrations
  ///        against the map: selection, solver, deskewing, with the grid replaced by the height
  ///        map's resolution and params.cells).
  Localizer(PriorMap map, const LocalizerParams& params, const SlamParams& slam);

  /// Starts tracking at `pose` (map frame) instead of searching: the first scan is registered
  /// around it.
  void setInitialPose(const Eigen::Isometry3d& pose);

  /// Processes one scan (vehicle frame; `point_times` as LidarOdometry::process).
  LocalizationStep process(double time, const PointCloud& points,
                           const std::vector<float>& point_times);
  /// The same, taking the scan over: where the odometry may have to start from it (while the
  /// odometry is stopped, every scan) it is kept without a copy, and `points` and `point_times`
  /// are left holding an earlier scan's buffers, for the caller to refill.
  LocalizationStep process(double time, PointCloud&& points, std::vector<float>&& point_times);

  const PriorMap& map() const { return map_; }
  const LocalizerParams& params() const { return params_; }

 private:
  /// process(); `owned` and `owned_times`, when given, are `points` and `point_times` themselves,
  /// which the scan may be swapped out of.
  LocalizationStep processScan(double time, const PointCloud& points,
                               const std::vector<float>& point_times, PointCloud* owned,
                               std::vector<float>* owned_times);
  /// The body twist per second over recent_poses_, first to last (at least two).
  Vector6d recentVelocity() const;
  /// The body twist per second over the localised scans of the last few intervals
  /// (localised_, gaps allowed), and where it carries the newest of them to `time`; false
  /// unless they span two intervals and the newest is a scan or two old. `dt`: the current
  /// scan's interval.
  bool mapVelocity(double time, double dt, Vector6d& velocity, Eigen::Isometry3d& start) const;
  /// Where a registration against the map starts.
  enum class Start {
    kPrediction,  ///< the odometry's prediction: its z, roll and pitch carried, tracking levels
    kFound,       ///< a place a search found: laid on the map's ground, tracking levels
    kSearch       ///< a search's start at a keyframe: laid on the ground, every level
  };
  /// One registration of the current frame against the map.
  struct Fit {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< map frame, levelled
    double rms = 0.0;      ///< RMS height error of the cells that found the map
    double inliers = 0.0;  ///< fraction of the selected cells that found the map
    double cost = 0.0;     ///< AlignmentResult::cost (unmatched cells as outliers)
    bool degenerate = true;
    /// Well conditioned, and min_inliers of the cells found the map.
    bool believable = false;
  };
  /// Registers the current frame against the map around `guess` (map frame); `degenerate`
  /// when there is no map or no frame there.
  Fit fit(const Eigen::Isometry3d& guess, Start start);
  /// fit(), and whether it is believable within `rms_bound`; fills step's rms and inliers and,
  /// if so, its pose.
  bool track(const Eigen::Isometry3d& guess, double rms_bound, LocalizationStep& step, Start start);
  /// The RMS a tracked registration may reach: rms_ratio times the recent median, max_rms at
  /// most.
  double trackingBound() const;
  /// Searches the whole map for the current scan; a place away from `prediction` (if not null)
  /// must fit clearly better than the prediction itself. \return whether a pose was found (then
  /// `found` holds it and `best_rms` its fit).
  bool search(const Eigen::Isometry3d* prediction, Eigen::Isometry3d& found, double& best_rms);
  /// Builds reference_ from the height map's window around `pose` unless it is already near there.
  /// \return whether the reference holds anything.
  bool referenceAround(const Eigen::Isometry3d& pose, bool force = false);
  /// `pose` with z, roll and pitch from the map's ground under the current frame.
  Eigen::Isometry3d levelled(const Eigen::Isometry3d& pose);

  PriorMap map_;
  LocalizerParams params_;
  SlamParams slam_;
  DloParams grid_;
  DirectAligner aligner_;
  int tracking_levels_ = 1;  ///< pyramid levels up to params.tracking_basin
  HeightFrame current_, reference_;
  Eigen::Isometry3d reference_pose_ = Eigen::Isometry3d::Identity();  ///< map frame
  bool reference_ready_ = false;
  GroundSurface ground_;  ///< the current frame's ground (fitted once per scan, when needed)
  bool ground_fitted_ = false;

  /// The odometry, run only while the map does not localise every scan (see process()):
  /// created again at the first scan that needs it, its own frame starting there.
  std::unique_ptr<LidarOdometry> odometry_;
  Eigen::Isometry3d last_odometry_ = Eigen::Isometry3d::Identity();  ///< odometry frame
  /// Body twist per second: the odometry's while it runs, else measured over recent_poses_
  /// (kVelocityIntervals intervals). It deskews the sweep and, while the map localises, predicts
  /// the motion.
  Vector6d velocity_ = Vector6d::Zero();
  /// The last localised scans in a row: time and pose (map frame), oldest first.
  std::deque<std::pair<double, Eigen::Isometry3d>> recent_poses_;
  /// The last localised scans (kVelocityIntervals + 1), in a row or not, cleared by a
  /// re-localisation: time and pose (map frame), oldest first.
  std::deque<std::pair<double, Eigen::Isometry3d>> localised_;
  bool fit_degenerate_ = false;   ///< the last fit that track() ran was degenerate
  bool conditioned_fix_ = false;  ///< the last scan was localised by a well-conditioned fit
  double last_time_ = 0.0;
  /// While the odometry is stopped: the last scan, for it to start from.
  PointCloud previous_points_;
  std::vector<float> previous_times_;
  double previous_time_ = 0.0;
  SweepPeriodEstimate period_;          ///< the scans' timestamps (estimated per-point times)
  std::vector<float> estimated_times_;  ///< per-point times estimated from azimuths
  size_t scans_ = 0;  ///< processed so far (after the first, there is a velocity to deskew with)
  bool tracking_ = false;  ///< a pose to predict from (a fix or an initial pose)
  bool fixed_ = false;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();  ///< map frame
  int unlocalised_run_ = 0;
  /// Scans still to confirm a re-localisation that jumped away from the odometry's pose, and
  /// that pose carried on by the odometry meanwhile (what tracking returns to if they fail).
  int probation_ = 0;
  Eigen::Isometry3d fallback_ = Eigen::Isometry3d::Identity();
  std::vector<double> recent_rms_;  ///< of the last localised scans, oldest first
  int since_search_ = 1 << 20;
};

}  // namespace dlo
