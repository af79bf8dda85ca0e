/// \file lidar_odometry.h
/// \brief Scan-to-reference odometry: constant-velocity prediction, deskewing, registration
/// against the previous scan, the last keyframe or a local height map, keyframe decisions.
#pragma once

#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "dlo/core/direct_aligner.h"
#include "dlo/core/ground_surface.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/local_height_map.h"
#include "dlo/core/sweep_timing.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/slam/reference_model.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// Time spent on one scan, milliseconds.
struct OdometryTimes {
  double deskew_ms = 0.0;
  StageTimes registration;    ///< the current frame's build (grid, gradients, selection) + solve
  double keyframe_ms = 0.0;   ///< decimating a new keyframe and rebuilding the reference
  double local_map_ms = 0.0;  ///< reference = scan_map: adding the scan to the map, new reference
  double ground_ms = 0.0;     ///< odometry.levelling: the ground's fit and its alignments
  double totalMs() const {
    return deskew_ms + registration.totalMs() + keyframe_ms + local_map_ms + ground_ms;
  }
};

/// Where a scan's per-point times came from.
enum class PointTimeSource {
  kNone,       ///< none: the scan was not deskewed (deskewing off, or the first scan)
  kMeasured,   ///< the input's own per-point times
  kFromOrder,  ///< estimated from azimuths, start and spin direction read off the point order
  kFromParams  ///< estimated from azimuths, start and spin direction from odometry.sweep_*
};

/// The revolution period to estimate per-point times with: odometry.sweep_period when set,
/// else `scans`' estimate from the timestamps (kDefaultSweepPeriod before the second scan).
double sweepPeriod(const OdometryParams& params, const SweepPeriodEstimate& scans);
/// Period assumed before a second scan's timestamp tells it (a 10 Hz sensor).
constexpr double kDefaultSweepPeriod = 0.1;

/// The per-point times to deskew `points` with, as the odometry takes them: `measured` when it
/// has one per point, else (params.estimate_times) estimated from the azimuths into `buffer`
/// over a revolution of `period` seconds (sweepPeriod()); empty when params.deskew is off or
/// `points` is. `source` says which.
const std::vector<float>& pointTimesFor(const PointCloud& points,
                                        const std::vector<float>& measured,
                                        const OdometryParams& params, double period,
                                        std::vector<float>& buffer, PointTimeSource& source);

/// The outcome of one scan.
struct OdometryStep {
  /// Pose of the vehicle at the scan's reference time in the odometry frame (the first scan's
  /// vehicle frame), before any loop closure.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  AlignmentResult registration;  ///< against the reference (none for the first scan)
  bool registered = false;       ///< false for the first scan and for empty scans
  /// The registration moved the pose farther from the constant-velocity prediction than
  /// odometry.max_prior_deviation, and the prediction itself fitted the scan better than the
  /// registrations from every start tried: the prediction was kept, and `registration`
  /// describes it (degenerate, its pose, unobserved covariance).
  bool rejected = false;
  /// Registrations run for this scan: 1, or more where the first disagreed with the prediction
  /// and other starts were tried (no motion, the last interval's motion).
  int starts = 1;
  /// Another heading fitted the coarsest level better than the first registration, and the
  /// scan was registered from there too (LidarOdometry::searchTurn) ...
  bool turn_searched = false;
  /// ... and that registration fitted the scan better: it stood for the first.
  bool turn_found = false;
  /// A registration contradicted the prediction and turned the scan more than the coarsest
  /// level's basin from it, and the scan was deskewed with other yaw rates within
  /// odometry.max_yaw_rate and registered again (the sweep's own rate: see
  /// LidarOdometry::process) ...
  bool rate_searched = false;
  /// ... and one of those rates fitted the scan best.
  bool rate_found = false;
  /// One of the other starts fitted the scan better than the registration from the prediction
  /// and gave the pose.
  bool alternative = false;
  /// The pose taken where the registration disagreed with the prediction fitted the scan with
  /// at most half the prediction's cost: the velocity is then measured without the
  /// odometry.max_acceleration and max_yaw_acceleration limits.
  bool convincing = false;
  /// The registration from the prediction could not observe a translation along which the
  /// velocity was uncertain (unmeasured or ageing): the scan's fit against the previous scan,
  /// evaluated over a grid of motions along it, had a unique and clearly better minimum, from
  /// which the scan was registered again and which gave the velocity
  /// (LidarOdometry::searchUnobserved).
  bool searched = false;
  /// Motions evaluated against the previous scan along an unobserved direction (0: no search).
  int search_starts = 0;
  /// With `searched`: the motion since the previous scan that the search found, per second
  /// (body twist), which becomes the velocity.
  Vector6d search_motion = Vector6d::Zero();
  /// With `searched`: the scans before this one whose motion along the searched directions was
  /// only predicted (a run of degenerate, rejected or empty scans), smoothed with the velocity the
  /// search found. Translations (odometry frame, metres) to add to the positions of the last
  /// backfill.size() scans before this one, oldest first; this scan and every later one move by
  /// backfill.back() (`pose` is not moved: it is relative to the previous scan as returned).
  /// The velocity along a direction that no scan observed follows a random walk (the filter's
  /// acceleration limits), so a velocity measured at the end of the run changes the run's
  /// velocities in proportion to the variance each had. Only where the velocity had never been
  /// measured along it (a drive that starts at speed on an open road, predicted at rest until a
  /// pole comes into view; then about all of the change), never to overrule a velocity measured
  /// before the run on one search's word. Empty otherwise.
  std::vector<Eigen::Vector3d> backfill;
  /// z, roll and pitch of `pose` were measured from the scan's ground (odometry.levelling);
  /// otherwise they are the prediction's.
  bool levelled = false;
  /// With `levelled`: the covariance the ground gave z, roll and pitch (GroundAlignment).
  Matrix6d ground_covariance = Matrix6d::Zero();
  /// Where the per-point times used for deskewing came from.
  PointTimeSource point_times = PointTimeSource::kNone;
  /// With times estimated from azimuths: the revolution period they assumed (seconds).
  double sweep_period = 0.0;
  bool new_keyframe = false;  ///< this scan became a keyframe
  /// The new keyframe's points (deskewed, vehicle frame, decimated to map_voxel within
  /// map_range); empty unless new_keyframe.
  WeightedCloud keyframe_cloud;
  /// Set once, on the second scan: the first keyframe's cloud deskewed now that a velocity is
  /// known (same decimation as keyframe_cloud); replaces that keyframe's cloud.
  WeightedCloud first_keyframe_cloud;
  OdometryTimes times;
};

/// DLO odometry over a stream of scans. Keeps only what the reference needs (the last scan's
/// frame, or the recent keyframes' decimated clouds), so memory does not grow with the stream.
class LidarOdometry {
 public:
  explicit LidarOdometry(const SlamParams& params);

  /// Processes the next scan.
  /// \param time seconds; must increase.
  /// \param points vehicle frame at `time`.
  /// \param point_times per-point seconds relative to `time`, or empty.
  OdometryStep process(double time, const PointCloud& points,
                       const std::vector<float>& point_times);

  /// Brings the buffers the next scan's grids are built in (about 7 MB at 600 x 600 cells) back
  /// into the cache, from which a keyframe's work evicts them (decimation, local map, loop
  /// search: some 15 MB of memory traffic): the scan after a keyframe then builds its grid as
  /// fast as the others. Read-only; SlamPipeline calls it at the end of a keyframe's scan.
  void warmCaches() const { current_.warmCaches(); }

  /// The parameters in use: the constructor's.
  const SlamParams& params() const { return params_; }

  /// Current velocity estimate: body twist per second.
  const Vector6d& velocity() const { return velocity_; }
  /// The per-point times the last process() deskewed with (pointTimesFor(); empty if none).
  /// Valid until the next process() call, and while the point_times passed to it live.
  const std::vector<float>& lastPointTimes() const { return *last_times_; }
  size_t frames() const { return frames_; }

 private:
  /// A registered pose far enough from the prediction to need other evidence (see
  /// decideByEvidence()): its translation or its rotation (counted as its displacement at
  /// solver.rotation_scale) beyond odometry.max_prior_deviation, bounds that widen with each
  /// consecutive rejection.
  bool disagrees(const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& pose) const;
  /// Registers from other starts (no motion, the last interval's motion) and returns the pose
  /// that fits the scan best, the prediction included; fills step.registration, starts,
  /// alternative and rejected.
  /// `first_start`: where step.registration started (the prediction, or a heading of
  /// searchTurn()); `prediction_cost`: the prediction's cost in the frame deskewed with the
  /// predicted motion.
  /// `deskewed_as`: deskews the current frame with the motion to the given pose and registers it
  /// from there (nothing without deskewing), for the best answer where the prior rejects it.
  Eigen::Isometry3d decideByEvidence(
      const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& first_start,
      double prediction_cost, double dt, OdometryStep& step,
      const std::function<std::optional<AlignmentResult>(const Eigen::Isometry3d&)>& deskewed_as);
  /// The per-point times to deskew `points` with: `measured` when it has one per point, else
  /// (odometry.estimate_times) estimated from the azimuths into estimated_times_; empty when
  /// deskewing is off. Sets step.point_times.
  const std::vector<float>& sweepTimes(const PointCloud& points, const std::vector<float>& measured,
                                       OdometryStep& step);
  /// One registration of a scan whose first registration disagreed with the prediction.
  struct Answer {
    AlignmentResult r;
    Eigen::Isometry3d pose;  ///< odometry frame
  };
  /// Where the registration from the prediction (step.registration, odometry-frame pose
  /// `first`) left a direction unobserved and the velocity is uncertain along it by more than
  /// the basin of the coarse levels over `dt` (motion_cov_): evaluates the fit against the
  /// previous scan over motions spread over two standard deviations along that direction; if
  /// one fits clearly better, registers from there against the reference and returns that pose
  /// (setting step.searched, search_motion and registration), else `first`. Counts the motions
  /// evaluated in step.search_starts.
  Eigen::Isometry3d searchUnobserved(const Eigen::Isometry3d& first, double dt, OdometryStep& step);
  /// The heading search (odometry.max_yaw_rate): the fit of the current frame at the coarsest
  /// level of both frames, at odometry-frame pose `first` turned about the vehicle by steps of
  /// a few degrees, as far as keeps the yaw rate since the last scan within max_yaw_rate over
  /// `dt`, leaving out those within two steps (`first`'s own basin). Returns the turned pose
  /// that fits best, where it fits better than `first`; nothing otherwise.
  std::optional<Eigen::Isometry3d> searchTurn(const Eigen::Isometry3d& first, double dt) const;
  /// Propagates motion_cov_ over `dt` (constant velocity, the acceleration limits as the
  /// velocity's random walk).
  void predictMotionCovariance(double dt);
  /// Fuses a registration (its pose and covariance against the reference) into motion_cov_.
  /// Returns, for x, y and yaw, the fraction of the registration's velocity (a pose error over
  /// `dt`) that the filter's gain credits to the velocity: near 1 where the registration
  /// constrains that direction much better than the prediction, near 0 where it does not.
  Eigen::Vector3d updateMotionCovariance(const AlignmentResult& r, double dt);
  /// Whether answers[best] (of the answers that fit within 10 % of the best, the nearest to the
  /// prediction) is to be believed over the prediction: it is well conditioned and fits better
  /// than the prediction by a margin that grows with its distance from the prior (a soft prior:
  /// the prediction or, for a scan where no start ended degenerate, whichever of the `likely`
  /// motions is nearer), more so where another start ended degenerate (a scan that constrains
  /// little).
  bool evidenceSupports(const std::vector<Answer>& answers, size_t best,
                        const Eigen::Isometry3d& predicted,
                        const std::vector<Eigen::Isometry3d>& likely, double prediction_cost) const;
  /// Whether some answer far from `winner` ended degenerate: a scan that constrains little, whose
  /// best fit is weak evidence.
  bool isWeak(const std::vector<Answer>& answers, const Answer& winner) const;
  /// The larger of the translation and the rotation (as its displacement at
  /// solver.rotation_scale) between two poses, metres.
  double deviation(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) const;
  /// The measured velocity, its change since the last one limited to the vehicle's
  /// odometry.max_acceleration and max_yaw_acceleration over `dt`.
  Vector6d limitAcceleration(const Vector6d& measured, double dt) const;
  /// Replaces a rejected registration by the prediction.
  void keepPrediction(const Eigen::Isometry3d& predicted, AlignmentResult& r) const;
  /// The part of a measured body twist carried to the next scan (prediction and deskewing).
  Vector6d carried(const Vector6d& v) const;
  /// odometry.levelling applies: on, with solver.dof = 3.
  bool levelling() const;
  /// `pose` (odometry frame) with its z, roll and pitch measured from the current scan's ground
  /// laid on the reference's ground (dlo::alignToGround), x, y and heading held; `pose` itself
  /// where levelling is off, there is no reference, or no ground to measure. The ground is
  /// fitted once per build of the current frame. Sets step.levelled and adds to ground_ms.
  Eigen::Isometry3d onGround(const Eigen::Isometry3d& pose, OdometryStep& step);
  /// The current scan has enough selected cells (solver.min_cells) to become a keyframe.
  bool hasStructure() const;
  bool needsKeyframe(const Eigen::Isometry3d& pose, const AlignmentResult& r) const;
  /// `points` as registered, moved by `motion` (the deskewing still pending, if it fits them).
  void addKeyframe(const Eigen::Isometry3d& pose, const PointCloud& points,
                   const SweepMotion& motion, OdometryStep& step);
  void redoFirstKeyframe(OdometryStep& step);
  /// A keyframe's points within map_range, decimated for the local map (`fine`,
  /// keyframe_voxel, 0 = every point; left empty unless the keyframe map is the reference)
  /// and for the long-term map (`coarse`, map_voxel).
  void decimate(const PointCloud& points, const SweepMotion& motion, WeightedCloud& fine,
                WeightedCloud& coarse);

  SlamParams params_;
  DirectAligner aligner_;
  HeightFrame current_;         ///< reused for every scan
  GroundSurface ground_;        ///< the current frame's ground, see onGround()
  bool ground_fitted_ = false;  ///< ground_ is that of current_ as last built
  PointCloud deskewed_;  ///< reference = scan_map: the scan deskewed, memory reused for every scan
  PointCloud near_;      ///< a keyframe's points within map_range, memory reused
  std::vector<float> estimated_times_;  ///< sweepTimes() of scans without times, memory reused
  SweepPeriodEstimate period_;          ///< the scans' timestamps, for odometry.sweep_period = 0
  const std::vector<float>* last_times_ = &estimated_times_;  ///< see lastPointTimes()
  /// What scans are registered against (odometry.reference).
  ReferenceModelPtr reference_;
  Eigen::Isometry3d last_pose_ = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d last_keyframe_pose_ = Eigen::Isometry3d::Identity();
  /// RMS height errors of the first accepted, non-degenerate fits against the last few new
  /// keyframes (at most kFreshFits), and whether the next such fit is still awaited: the fit a
  /// new keyframe gives here, see needsKeyframe().
  std::deque<double> fresh_fits_;
  bool awaiting_fresh_fit_ = false;
  Vector6d velocity_ = Vector6d::Zero();
  /// Uncertainty of the constant-velocity prediction in the plane, a small Kalman filter beside
  /// the velocity: the predicted pose's error relative to the reference (body x, y, yaw) and the
  /// velocity's error (vx, vy, yaw rate), rotations scaled to metres by solver.rotation_scale.
  /// It starts with the velocity unknown (odometry.max_speed), grows with the acceleration
  /// limits and shrinks along what registrations observe. It decides where and how far a
  /// degenerate registration searches (searchUnobserved()) and how much of a registration's
  /// planar velocity is taken (updateMotionCovariance()).
  Eigen::Matrix<double, 6, 6> motion_cov_ = Eigen::Matrix<double, 6, 6>::Zero();
  /// The last scan, kept only where its registration left something unobserved (or it was the
  /// first): its points as given, their times and the velocity it was deskewed with, for
  /// searchUnobserved() on the next scan.
  PointCloud previous_points_;
  std::vector<float> previous_times_;
  Vector6d previous_velocity_ = Vector6d::Zero();
  HeightFrame previous_frame_;  ///< built from them when a search needs it, memory reused
  /// A scan interval whose motion along some direction was only predicted: its length, the
  /// orientation at its end (odometry frame) and the velocity's prior covariance over it (as
  /// motion_cov_'s velocity block).
  struct UnobservedInterval {
    double dt = 0.0;
    Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
    Eigen::Matrix3d velocity_cov = Eigen::Matrix3d::Zero();
  };
  /// The current run of such intervals, up to the previous scan (OdometryStep::backfill).
  std::deque<UnobservedInterval> unobserved_run_;
  /// Fills step.backfill from unobserved_run_: the velocity along each search axis (unit,
  /// vehicle frame, planar; the search's grid spacing along it in `spacings`) moved by `found`
  /// (metres over `dt`, vehicle frame). Called by searchUnobserved() before the scan updates
  /// motion_cov_, whose velocity block is then the prior over this interval.
  void backfillRun(const std::vector<Eigen::Vector3d>& axes, const std::vector<double>& spacings,
                   const Eigen::Vector3d& found, double dt, OdometryStep& step) const;
  /// The first scan as measured: it could not be deskewed (no velocity yet), so it is redone
  /// once the second scan gives a velocity, otherwise the whole local map stays distorted.
  PointCloud first_points_;
  std::vector<float> first_times_;
  double last_time_ = 0.0;
  Eigen::Isometry3d before_last_pose_ = Eigen::Isometry3d::Identity();
  double before_last_time_ = 0.0;
  size_t frames_ = 0;
  size_t velocity_updates_ = 0;  ///< scans the velocity was measured from
  /// Velocity measurements since the start or since a run of rejections ended: the prediction
  /// may reject a registration only after kSettledVelocityUpdates of them (disagrees()).
  size_t settled_updates_ = 0;
  int rejected_run_ = 0;  ///< consecutive rejected registrations
  /// Whether the last scan measured its motion (registered, believed, well conditioned).
  bool last_measured_ = false;
};

}  // namespace dlo
