#include "dlo/slam/lidar_odometry.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <Eigen/Eigenvalues>

#include "dlo/core/deskew.h"
#include "dlo/core/ground_alignment.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/sweep_timing.h"
#include "dlo/core/units.h"

namespace dlo {

namespace {
/// Variance of what a rejected registration could not tell, as DirectAligner gives directions it
/// cannot observe.
constexpr double kUnobservedVariance = 1e6;
/// Two registrations of one scan closer than this fraction of odometry.max_prior_deviation give
/// the same answer.
constexpr double kSameAnswer = 0.25;
/// Answers whose cost is within this fraction of the best answer's fit the scan alike: the one
/// nearest the prediction is taken among them (LidarOdometry::decideByEvidence).
constexpr double kClearMargin = 0.1;
/// Metres (rotations at solver.rotation_scale): see LidarOdometry::evidenceSupports().
constexpr double kPriorScale = 2.0;
/// Metres: the translation scale of the soft prior for an answer that moves the scan towards
/// the newest keyframe (LidarOdometry::evidenceSupports()).
constexpr double kTowardsKeyframeScale = 0.5;
/// An answer whose cost is this fraction below the prediction's is believed however far it is.
constexpr double kConvincing = 0.5;
/// Radians between the headings the turn search (LidarOdometry::searchTurn) compares: within the
/// basin of the coarsest level's cells (0.8 m at the dense profile's 0.1 m) for structure up to
/// about 20 m away.
constexpr double kTurnStep = 2.0 * kDeg;
/// Headings nearer than this many steps to the registered one lie in its own basin: the search
/// compares the others.
constexpr int kTurnBasinSteps = 2;
/// Times a scan whose registration contradicts the prediction is deskewed again with the motion
/// it measured and registered again.
constexpr int kRedeskewIterations = 2;
/// Yaw rates tried on each side of the best one for the deskewing of such a scan, spread over
/// odometry.max_yaw_rate (60 deg/s apart at 180 deg/s; LidarOdometry::process()).
constexpr int kRateSteps = 3;

/// The planar part (x, y, yaw) of a body twist: what the velocity carries from scan to scan
/// without levelling (LidarOdometry::carried()).
Vector6d planar(Vector6d v) {
  v(2) = v(3) = v(4) = 0.0;
  return v;
}
/// Variance above which a direction of a registration's covariance is one it could not observe
/// (DirectAligner gives those kUnobservedVariance).
constexpr double kUnobservedThreshold = 1e5;
/// Finest cells the prediction's uncertainty (two standard deviations) must span along an
/// unobserved direction before LidarOdometry::searchUnobserved searches it: the coarsest level's
/// cell, within whose basin the registration finds the structure from the prediction itself.
constexpr double kSearchBasin = 8.0;
/// Cell residuals the grid of LidarOdometry::searchUnobserved may evaluate in all (about a
/// millisecond), and the poses it has at least.
constexpr double kSearchResiduals = 4e5;
/// Fresh-keyframe fits whose median is the keyframe rule's baseline (needsKeyframe()): a few
/// keyframes' worth, so that one scan with a passing truck does not set it.
constexpr size_t kFreshFits = 5;
constexpr double kMinSearchPoses = 81;
/// Standard deviation of the yaw rate before any is measured, deg/s.
constexpr double kInitialYawRateSigma = 45.0;
/// Velocity measurements before the constant-velocity prediction is trusted to reject a scan.
constexpr size_t kSettledVelocityUpdates = 5;
/// A velocity variance that falls by more than this factor from one scan to the next had the
/// velocity measured (a degenerate registration takes a few parts in a thousand off it).
constexpr double kMeasuredVarianceDrop = 2.0;
/// The share of its variance now that the velocity had at the start of a run, below which it had
/// been measured before the run (backfillRun(); never measured: the share is about 1).
constexpr double kUnmeasuredShare = 0.5;
/// A search's velocity change smooths the run before it only when larger than this many steps
/// of the search's grid (backfillRun()).
constexpr double kBackfillSteps = 2.0;
/// Longest run of scans that a search's velocity smooths (OdometryStep::backfill): a minute at
/// 10 Hz.
constexpr size_t kMaxUnobservedRun = 600;

/// The planar part (x, y, yaw scaled by `rs`) of a left perturbation of `pose` (the current
/// scan in the reference, as a registration's covariance has it) as a perturbation in the
/// vehicle's own frame: exp(xi) pose = pose exp(Ad(pose^-1) xi).
Eigen::Matrix3d leftToBody(const Eigen::Isometry3d& pose, double rs) {
  const double yaw = yawPitchRoll(pose.linear()).x();
  const Eigen::Matrix2d rt = Eigen::Rotation2Dd(yaw).toRotationMatrix().transpose();
  const Eigen::Vector2d t = pose.translation().head<2>();
  Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
  a.topLeftCorner<2, 2>() = rt;
  a.topRightCorner<2, 1>() = rt * Eigen::Vector2d(-t.y(), t.x()) / rs;
  a(2, 2) = 1.0;
  return a;
}

/// Where x, y and yaw sit in a 6-vector twist (x, y, z, wx, wy, wz).
constexpr int kPlanar[3] = {0, 1, 5};
/// Metres per unit of the planar component `i` (x, y, yaw): 1, 1 and `rs`.
double planarScale(int i, double rs) {
  return i == 2 ? rs : 1.0;
}

/// The x, y, yaw block of a 6 x 6 twist covariance, yaw scaled to metres by `rs`.
Eigen::Matrix3d planarScaled(const Matrix6d& cov, double rs) {
  Eigen::Matrix3d c;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      c(i, j) = cov(kPlanar[i], kPlanar[j]) * planarScale(i, rs) * planarScale(j, rs);
  return c;
}

/// Writes `c` (x, y, yaw scaled by `rs`, as planarScaled() gives it) back into the x, y, yaw
/// block of `cov`.
void setPlanarScaled(const Eigen::Matrix3d& c, double rs, Matrix6d& cov) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      cov(kPlanar[i], kPlanar[j]) = c(i, j) / (planarScale(i, rs) * planarScale(j, rs));
}

/// The twist of a planar motion d (x, y, yaw scaled by `rs`).
Vector6d planarTwist(const Eigen::Vector3d& d, double rs) {
  Vector6d xi = Vector6d::Zero();
  for (int i = 0; i < 3; ++i) xi(kPlanar[i]) = d(i) / planarScale(i, rs);
  return xi;
}

/// Points within `range` metres (horizontally) of the vehicle, what a keyframe keeps, into
/// `out`: moved by `motion` if it fits them, in the same pass (a deskewed copy of the whole
/// sweep first cost a pass and a megabyte more per keyframe). Moved a batch at a time
/// (SweepMotion::apply finds the bins of a batch together, as the rasterisation does).
void nearPoints(const PointCloud& points, const SweepMotion& motion, double range,
                PointCloud& out) {
  out.resize(points.size());  // at most every point; cut to those kept at the end
  const float r2 = static_cast<float>(range * range);
  size_t kept = 0;
  if (!motion.fits(points.size())) {
    for (const Eigen::Vector3f& p : points) {
      if (p.head<2>().squaredNorm() <= r2) out[kept++] = p;
    }
  } else {
    constexpr size_t kBatch = 256;
    Eigen::Vector3f moved[kBatch];
    for (size_t first = 0; first < points.size(); first += kBatch) {
      const size_t n = std::min(kBatch, points.size() - first);
      motion.apply(first, points.data() + first, n, moved);
      for (size_t k = 0; k < n; ++k) {
        if (moved[k].head<2>().squaredNorm() <= r2) out[kept++] = moved[k];
      }
    }
  }
  out.resize(kept);
}
}  // namespace

LidarOdometry::LidarOdometry(const SlamParams& params)
    : params_(params),
      aligner_(params.registration.solver),
      reference_(ReferenceModel::make(params)) {
  // The scan map (dlo::LocalHeightMap) keeps no centroids of its cells: a scan's cells are
  // compared with it at their centres, as the map's are (HeightFrame::placeCellsOnCentroids()).
  if (params_.odometry.reference == Reference::kScanMap)
    params_.registration.selection.centroid_levels = 0;
}

OdometryStep LidarOdometry::process(double time, const PointCloud& points,
                                    const std::vector<float>& point_times) {
  OdometryStep step;
  const DloParams& reg = params_.registration;
  const double dt = frames_ == 0 ? 0.0 : time - last_time_;
  // What is left of the yaw rate over this interval where no scan measures it (see
  // OdometryParams::yaw_rate_decay): the velocity update below decays its part of the rate that
  // the registration does not observe, a scan that measured nothing decays all of it.
  const double tau = params_.odometry.yaw_rate_decay;
  const double yaw_rate_kept = tau > 0.0 && dt > 0.0 && dt < 1.0 ? std::exp(-dt / tau) : 1.0;
  // Constant velocity: the motion of the last interval, repeated.
  Eigen::Isometry3d predicted =
      dt > 0.0 && dt < 1.0 ? last_pose_ * expSE3(velocity_ * dt) : last_pose_;
  if (frames_ == 0) {
    // Nothing is known of the velocity yet: the vehicle may be moving at any speed up to
    // odometry.max_speed (two standard deviations).
    const double rs = reg.solver.rotation_scale;
    const double v = 0.5 * params_.odometry.max_speed;
    const double w = kInitialYawRateSigma * kDeg * rs;
    motion_cov_.setZero();
    motion_cov_.diagonal().tail<3>() << v * v, v * v, w * w;
  } else if (dt > 0.0) {
    predictMotionCovariance(std::min(dt, 1.0));
  }
  // The velocity's prior over this interval, before the scan is registered (the run below).
  const Eigen::Matrix3d velocity_prior = motion_cov_.bottomRightCorner<3, 3>();

  // With the scan map (reference = scan_map) every sweep has two readers, its grid and the map: it
  // is deskewed once, into a buffer kept across scans (applying the motion in both costs more).
  // Otherwise it is deskewed while it is rasterised, with no copy (deskew_ms is then the motion
  // table only and grid_ms includes moving the points), and copied only for a keyframe.
  Stopwatch deskew_watch;
  period_.add(time);
  const std::vector<float>& times = sweepTimes(points, point_times, step);
  last_times_ = &times;
  const bool deskew = !times.empty() && frames_ > 0;
  const bool copy = deskew && reference_->deskewsACopy();
  SweepMotion motion;
  const SweepMotion none;
  const PointCloud* cloud_ptr = &points;
  const SweepMotion* pending_ptr = &none;  // what the cloud still has to be moved by
  // Frame to frame, this scan becomes the next reference; otherwise it never is one.
  const FrameUse use = reference_->currentUse();
  // The current frame, deskewed with the body twist `v`; the deskewing's time (the motion
  // table, and the copy for the scan map) is added to deskew_ms.
  Vector6d deskew_velocity = Vector6d::Zero();  // what the current frame was deskewed with
  const auto build = [&](const Vector6d& v) {
    Stopwatch w;
    deskew_velocity = deskew ? v : Vector6d::Zero();
    if (deskew) motion = SweepMotion(times, v);
    if (copy) dlo::deskew(points, motion, deskewed_);
    cloud_ptr = copy ? &deskewed_ : &points;
    pending_ptr = copy || !deskew ? &none : &motion;
    step.times.deskew_ms += w.elapsedMs();
    current_.build(*cloud_ptr, *pending_ptr, reg.grid, reg.selection, reg.includeGround(), use);
    ground_fitted_ = false;
  };
  step.times.deskew_ms = deskew_watch.elapsedMs();
  build(velocity_);
  step.times.registration = current_.buildTimes();
  // Frames built again (a registration that contradicts the prediction) add to these.
  const auto rebuilt = [&step, this] { step.times.registration += current_.buildTimes(); };

  Eigen::Isometry3d pose = predicted;
  Eigen::Vector3d velocity_gain = Eigen::Vector3d::Ones();
  if (reference_->ready() && !current_.empty()) {
    // The prediction carries the planar motion only: its height and tilt come from the ground
    // under it, so that x, y and yaw are registered with the cells at their true heights (a
    // height error shifts a registration towards a kerb on one side).
    predicted = onGround(predicted, step);
    const bool prediction_levelled = step.levelled;
    const Eigen::Isometry3d to_reference = reference_->pose().inverse();
    step.registration = aligner_.align(reference_->frame(), current_, to_reference * predicted);
    pose = reference_->pose() * step.registration.pose;
    step.registered = true;
    step.times.registration.solve_ms += step.registration.times.solve_ms;
    // The prediction's fit, in the frame deskewed with the predicted motion (negative: not
    // evaluated).
    double prediction_cost = -1.0;
    const bool timed = dt > 0.0 && dt < 1.0;
    Eigen::Isometry3d first_start = predicted;  // where step.registration started
    if (timed && !step.registration.degenerate && velocity_updates_ >= kSettledVelocityUpdates) {
      // A turn begun faster than the coarsest level's basin reaches registers near its start
      // however wrong that is: a VLP-16 robot at rest that began to turn on the spot at 150
      // deg/s (15 deg per sweep) registered 1 deg per scan, and its heading ended the turn
      // about 90 deg off. Where another heading fits the coarsest level better than the answer does
      // (searchTurn()), the scan is registered from there as well, and the better fit at the
      // finest level is the scan's registration, which the prior then weighs as any other
      // (decideByEvidence(), where it disagrees with the prediction). Only once the velocity
      // has been measured: headings compared where the translation is still a guess (a VLP-16
      // lap starting at 10 m/s, predicted at rest) fitted its first scans better turned, and
      // the lap fell 1.2 m short by scan 15 instead of 0.6 m.
      if (const std::optional<Eigen::Isometry3d> turned = searchTurn(pose, dt)) {
        const Eigen::Isometry3d start = onGround(*turned, step);
        const AlignmentResult r =
            aligner_.align(reference_->frame(), current_, to_reference * start);
        step.times.registration.solve_ms += r.times.solve_ms;
        step.turn_searched = true;
        if (!r.degenerate && r.cost < step.registration.cost) {
          step.turn_found = true;
          step.registration = r;
          pose = reference_->pose() * r.pose;
          first_start = start;
        }
      }
    }
    bool doubtful = timed && disagrees(predicted, pose);
    if (timed && !doubtful && params_.odometry.recheck_worse_fits &&
        !step.registration.degenerate &&
        deviation(predicted, pose) > kSameAnswer * params_.odometry.max_prior_deviation) {
      // Moved from the prediction by more than tells two answers apart, yet fitting the scan
      // worse than the prediction: no better answer was found (OdometryParams::
      // recheck_worse_fits).
      prediction_cost = aligner_.cost(reference_->frame(), current_, to_reference * predicted);
      doubtful = prediction_cost < step.registration.cost;
    }
    if (doubtful) {
      bool as_predicted = true;  // the current frame is deskewed with the predicted motion
      if (prediction_cost < 0.0) {
        prediction_cost = aligner_.cost(reference_->frame(), current_, to_reference * predicted);
      }
      if (deskew && !step.registration.degenerate) {
        // The scan was deskewed with the predicted motion, which its registration contradicts:
        // deskewed with the motion it measured, it is registered again (a robot that begins to
        // turn on the spot at 90 deg/s turns 9 deg within the sweep, and a sweep deskewed as
        // if it stood still registers several degrees off). A motion that is right makes the
        // scan fit better once deskewed with it; one that does not is no answer (a wrong basin
        // deskewed with its own motion can drift further). Each iteration deskews with the mean
        // of the motion it deskewed with and the one it measured: the registered turn falls
        // as the deskewing's turn rises, by about 0.7 times as much, so deskewed with the
        // measured motion alone the iterations overshoot in turn (an HDL-64 robot beginning to
        // turn on the spot at 9 deg per scan: 12.9, 6.0, 10.9 deg, each with 0.2-0.5 m of
        // translation; with the mean: 11.9, 8.5, 8.3 deg, within 0.04 m). Of the first
        // registration and the iterations, the best fit stands, not the last: the sweep lies in
        // the interval after the scan's pose, and the motion measured over the one before is
        // not the sweep's where the motion changes (a robot that stopped turning between two
        // scans turned 6 deg before this sweep and none during it: deskewed with the first
        // answer's motion, near standing still, it fitted at a third of the prediction's cost;
        // deskewed once more with the 6 deg it then measured, worse than the first). Only the
        // rotation is taken from the answers; the translation stays the one the scan was
        // deskewed with. A sweep smeared by a turn registers with a translation the vehicle did
        // not make (a point r from the sensor moved by an angle that grows over the sweep shifts
        // the sweep's fit by about r times the smear over 2 pi), which deskewing with it then
        // builds into the sweep: a robot beginning to turn on the spot at 150 deg/s (15 deg
        // within the sweep) registered its first such scan 0.55 m away, its answers after two
        // iterations with the whole motion still 0.43 m away, and the prior rejected them and
        // the next four scans'.
        as_predicted = false;
        // How far the registration turned the scan from the prediction.
        const double turned_off = std::abs(yawPitchRoll((predicted.inverse() * pose).linear()).x());
        AlignmentResult r = step.registration;
        AlignmentResult best_r = r;
        Eigen::Isometry3d best_pose = pose;
        Vector6d best_velocity = deskew_velocity;
        for (int k = 0; k < kRedeskewIterations; ++k) {
          // The rotation measured; the translation the deskewing had (see above).
          Vector6d measured = carried(logSE3(last_pose_.inverse() * pose) / dt);
          measured.head<3>() = deskew_velocity.head<3>();
          build(0.5 * (deskew_velocity + measured));
          rebuilt();
          r = aligner_.align(reference_->frame(), current_, to_reference * pose);
          step.times.registration.solve_ms += r.times.solve_ms;
          const Eigen::Isometry3d moved = reference_->pose() * r.pose;
          const bool settled =
              deviation(moved, pose) < kSameAnswer * params_.odometry.max_prior_deviation;
          if (!r.degenerate && r.cost < best_r.cost) {
            best_r = r;
            best_pose = moved;
            best_velocity = deskew_velocity;
          }
          pose = moved;
          if (settled || r.degenerate) break;
        }
        // The sweep's own yaw rate. The interval before the scan's pose measures its motion, but
        // the sweep lies in the interval after it: a robot at rest that begins to turn on the
        // spot at 150 deg/s turns 2 deg by the pose and 15 deg within the sweep, and no motion
        // measured over the interval deskews such a sweep (a sweep deskewed with a rate 13 deg
        // per sweep wrong registers 0.3-0.5 m from where it was taken, and the prior rejected
        // it and the next four). Rates spread over odometry.max_yaw_rate (kRateSteps on each
        // side of the best so far) are tried, then half a step on each side of the best of
        // them: each deskews the sweep, which is registered from the best pose; the best fit
        // stands. Only where the registration turned the scan from the prediction by more than
        // the coarsest level's basin (kTurnBasinSteps turn steps): a yaw rate that changed by
        // less is followed by the iterations above, and the sparse sensors' fits, compared over
        // differently deskewed sweeps, then picked wrong rates in the corners of car drives
        // (VLP-16 `abrupt` 0.39 -> 0.68 % drift, geometric mean of three seeds).
        const double reach = params_.odometry.max_yaw_rate * kDeg;
        if (reach > 0.0 && turned_off > kTurnBasinSteps * kTurnStep) {
          const double centre = best_velocity(5);
          const double step_rate = reach / kRateSteps;
          const auto try_rate = [&](double rate) {
            if (std::abs(rate) > reach) return;
            Vector6d v = best_velocity;
            v(5) = rate;
            build(v);
            rebuilt();
            const AlignmentResult rr =
                aligner_.align(reference_->frame(), current_, to_reference * best_pose);
            step.times.registration.solve_ms += rr.times.solve_ms;
            step.rate_searched = true;
            if (!rr.degenerate && rr.cost < best_r.cost) {
              best_r = rr;
              best_pose = reference_->pose() * rr.pose;
              best_velocity = deskew_velocity;
              step.rate_found = true;
            }
          };
          for (int k = 1; k <= kRateSteps; ++k) {
            try_rate(centre - k * step_rate);
            try_rate(centre + k * step_rate);
          }
          const double found = best_velocity(5);
          try_rate(found - 0.5 * step_rate);
          try_rate(found + 0.5 * step_rate);
        }
        if (best_velocity != deskew_velocity) {
          build(best_velocity);
          rebuilt();
        }
        as_predicted = best_velocity == velocity_;
        r = best_r;
        pose = best_pose;
        step.registration = r;
      }
      // The best answer, should the prior reject it, is registered again in the frame deskewed
      // with its own motion (see decideByEvidence()).
      const auto deskewed_as = [&](const Eigen::Isometry3d& answer) {
        if (!deskew) return std::optional<AlignmentResult>();
        build(carried(logSE3(last_pose_.inverse() * answer) / dt));
        rebuilt();
        as_predicted = false;
        const AlignmentResult r =
            aligner_.align(reference_->frame(), current_, to_reference * answer);
        step.times.registration.solve_ms += r.times.solve_ms;
        ++step.starts;
        return std::optional<AlignmentResult>(r);
      };
      pose = decideByEvidence(predicted, first_start, prediction_cost, dt, step, deskewed_as);
      if (step.rejected && !as_predicted) {
        build(velocity_);  // the prediction stands: so does the deskewing it implies
        rebuilt();
      }
    }
    if (!step.rejected && step.starts == 1 && step.registration.degenerate && dt > 0.0 &&
        dt < 1.0) {
      pose = searchUnobserved(pose, dt, step);
    }
    velocity_gain = updateMotionCovariance(step.registration, dt);
    if (!step.rejected && rejected_run_ >= params_.odometry.max_rejected_scans) {
      // A run of rejections ended by believing the registration again: the jump back makes
      // the next predictions wrong for a while, so the velocity must settle again before the
      // prediction may reject anything (otherwise the runs repeat; seen on HDL-32 drives). The
      // velocity measured before the run still limits how fast the next ones change: a wrong
      // jump believed here (34 deg on a simulated VLP-16 drive) otherwise became a velocity of
      // -215 deg/s and 35 m/s within five scans, and the drive was lost.
      settled_updates_ = 0;
      // The scan map may be what went wrong (a bad scan inserted before the run): it restarts
      // from this scan rather than keep pulling the next ones back.
      reference_->restartAfterRejections();
    }
    rejected_run_ = step.rejected ? rejected_run_ + 1 : 0;
    if (!step.rejected) {
      // x, y and yaw registered: z, roll and pitch from the ground at that place and heading
      // (a rejected scan keeps the prediction, levelled above).
      pose = onGround(pose, step);
      step.registration.pose = to_reference * pose;
      if (step.levelled) {
        // The 3-DoF registration left z, roll and pitch unobserved (1e6): the ground measured
        // them, and the pose graph's edges carry that instead of a loose cap, which let loop
        // closures bend the trajectory's height and tilt (rotational drift after closure 1.17
        // deg/100 m on the demo drive against 0.35 before).
        Matrix6d& c = step.registration.covariance;
        for (int i : {2, 3, 4}) {
          c.row(i).setZero();
          c.col(i).setZero();
        }
        c += step.ground_covariance;
      }
    } else {
      step.levelled = prediction_levelled;
    }
  }
  step.pose = pose;

  // A scan that was not registered, or whose registration was rejected, measured nothing: the
  // velocity stays as it was. Recomputing it over two intervals from the kept prediction would
  // drag in the interval before, often the one where the trouble started.
  if (frames_ > 0 && dt > 0.0 && dt < 1.0 && step.registered && !step.rejected) {
    // The velocity is measured over the last two intervals, not one. Deskewing with a velocity
    // error d rotates the scan by about d/2, which the registration turns into a pose error of
    // opposite sign, which the next one-interval velocity doubles: a period-2 oscillation that
    // grew without bound in simulated turns. Over two intervals the loop gain drops below one.
    const bool two = frames_ >= 2 && time - before_last_time_ < 1.0;
    const Eigen::Isometry3d& from = two ? before_last_pose_ : last_pose_;
    // See carried(): with levelling the whole motion, otherwise its planar part.
    const Vector6d v =
        carried(logSE3(from.inverse() * pose) / (two ? time - before_last_time_ : dt));
    if (step.searched) {
      // The velocity along what the reference could not observe was unknown or ageing, and the
      // previous scan has just measured it: that interval's motion is the velocity (a finite
      // difference over two intervals would average in the one the prior guessed).
      for (int i : kPlanar) velocity_(i) = step.search_motion(i);
    } else {
      // A registration that disagreed with the prediction and halved its cost is a measurement
      // the scan insists on (step.convincing): its yaw rate is taken as measured. Limited, a
      // robot that begins to turn on the spot at 90 deg/s was predicted and deskewed 12 deg/s
      // faster each scan for eight scans, each registered 6 deg from its prediction, and ended
      // its turns up to half a degree off. Its speed is still limited (max_acceleration): what
      // a vehicle's speed can do within a scan does not depend on how well a scan fits, and
      // a convincing fit can carry a translation beside the turn it measured (an HDL-64 robot
      // that began to turn on the spot registered 0.5 m away, and the 5 m/s taken from that
      // scan put the next two predictions 1-2 m off: ATE 0.11 m against 0.06 m limited).
      Vector6d measured = v;
      if (velocity_updates_ >= kSettledVelocityUpdates) {
        const Vector6d limited = limitAcceleration(v, dt);
        if (step.convincing) {
          measured.head<2>() = limited.head<2>();
        } else {
          measured = limited;
        }
      }
      Vector6d before = velocity_;
      before(5) *= yaw_rate_kept;
      velocity_ = measured;
      // In the plane, the measured velocity is weighed against the prediction's by the motion
      // filter's gain (velocity_gain): a registration that constrains a direction well moves
      // the velocity nearly all the way, one with a few cells of structure (the end of a street
      // before an open field: 27-69 cells, yaw jumping 0.2 deg between scans) or none along a
      // direction barely at all. Taken whole, such scans set a yaw rate of 1.3 deg/s that the
      // open field then carried for 60 m. A convincing registration is taken whole: the scan
      // has shown the prediction's model wrong, which the filter's acceleration limits do not
      // describe (a robot turning on the spot lagged the turn by several scans).
      if (!step.convincing) {
        for (int k = 0; k < 3; ++k) {
          const int i = kPlanar[k];
          velocity_(i) = before(i) + velocity_gain(k) * (measured(i) - before(i));
        }
      }
    }
    ++velocity_updates_;
    ++settled_updates_;
  } else {
    velocity_(5) *= yaw_rate_kept;
  }
  if (frames_ == 1 && !first_points_.empty()) redoFirstKeyframe(step);

  // The second scan's fit is against the first as measured, not deskewed (redone only now): it
  // says nothing about what a keyframe gives.
  if (awaiting_fresh_fit_ && frames_ > 1 && step.registered && !step.rejected &&
      !step.registration.degenerate) {
    fresh_fits_.push_back(step.registration.rms_height_error);
    if (fresh_fits_.size() > kFreshFits) fresh_fits_.pop_front();
    awaiting_fresh_fit_ = false;
  }

  Stopwatch keyframe_watch;
  const bool first = frames_ == 0;
  if (!current_.empty() && (first || (hasStructure() && needsKeyframe(pose, step.registration)))) {
    addKeyframe(pose, *cloud_ptr, *pending_ptr, step);
    if (first && !times.empty()) {
      first_points_ = points;
      first_times_ = times;
    }
  }
  step.times.keyframe_ms = keyframe_watch.elapsedMs();
  // The reference learns of the scan: frame to frame it becomes the next reference, the scan
  // map takes it if its pose was measured.
  Stopwatch map_watch;
  reference_->afterScan(current_, *cloud_ptr, pose, first || (step.registered && !step.rejected));
  step.times.local_map_ms = map_watch.elapsedMs();

  // A scan whose registration could not observe everything may be the previous scan a search
  // needs next time (searchUnobserved()): its points, times and deskewing velocity are kept.
  if (params_.odometry.max_speed > 0.0 && !current_.empty() &&
      (first || !step.registered || step.registration.degenerate)) {
    previous_points_ = points;
    previous_times_ = times;
    previous_velocity_ = deskew_velocity;
  } else if (!previous_points_.empty()) {
    previous_points_.clear();
    previous_times_.clear();
  }
  // The run of scans whose motion was only predicted along some direction (degenerate, rejected
  // or empty), which a later search's velocity smooths (backfillRun()); any other scan, the
  // search's included, ends it.
  if (frames_ > 0 && dt > 0.0 && dt < 1.0 && !step.searched &&
      (!step.registered || step.rejected || step.registration.degenerate)) {
    unobserved_run_.push_back(UnobservedInterval{dt, pose.linear(), velocity_prior});
    if (unobserved_run_.size() > kMaxUnobservedRun) unobserved_run_.pop_front();
  } else {
    unobserved_run_.clear();
  }
  last_measured_ = step.registered && !step.rejected && !step.registration.degenerate;
  before_last_pose_ = last_pose_;
  before_last_time_ = last_time_;
  last_pose_ = pose;
  last_time_ = time;
  ++frames_;
  return step;
}

Eigen::Isometry3d LidarOdometry::decideByEvidence(
    const Eigen::Isometry3d& predicted, const Eigen::Isometry3d& first_start,
    double prediction_cost, double dt, OdometryStep& step,
    const std::function<std::optional<AlignmentResult>(const Eigen::Isometry3d&)>& deskewed_as) {
  // The prediction is a guess from the past; the scan is the measurement. A registration far
  // from the prediction is either right (the vehicle stopped turning, braked, began to turn on
  // the spot) or in a wrong basin (a large moving object, a scene that constrains little). The
  // scan is registered again from other starts: no motion since the last scan, the last
  // interval's motion as measured (the prediction averages two intervals and limits the
  // change), the prediction with its yaw rate stopped, and the first answer mirrored about the
  // prediction (which probes the basin from the other side where the others coincide with the
  // prediction, as for a robot at rest that begins to turn on the spot). Every answer is scored
  // by its fit: the mean robust cost of the same cells (AlignmentResult::cost). See
  // evidenceSupports() for what is then believed.
  const OdometryParams& o = params_.odometry;
  const Eigen::Isometry3d to_reference = reference_->pose().inverse();
  const Eigen::Isometry3d first = reference_->pose() * step.registration.pose;
  // The prediction is a start too where the first answer began elsewhere (searchTurn()).
  std::vector<Eigen::Isometry3d> starts = {
      predicted, last_pose_, predicted * expSE3(-logSE3(predicted.inverse() * first))};
  // Motions other than the prediction that the prior holds as likely (evidenceSupports()): the
  // last interval's motion continued, where the last scan measured it, and the prediction with
  // its yaw rate stopped. Both are starts too.
  std::vector<Eigen::Isometry3d> likely;
  if (frames_ >= 2 && last_time_ - before_last_time_ > 0.0 &&
      last_time_ - before_last_time_ < 1.0) {
    const Vector6d last =
        logSE3(before_last_pose_.inverse() * last_pose_) * (dt / (last_time_ - before_last_time_));
    starts.push_back(last_pose_ * expSE3(last));
    if (last_measured_) likely.push_back(starts.back());
  }
  Vector6d straight = velocity_;
  straight(5) = 0.0;
  starts.push_back(last_pose_ * expSE3(straight * dt));
  likely.push_back(starts.back());
  std::vector<Answer> answers = {{step.registration, first}};
  // Starts closer than this to one already tried would end in the same place; answers closer
  // than this are the same answer.
  const double same = kSameAnswer * o.max_prior_deviation;
  std::vector<Eigen::Isometry3d> tried = {first_start};
  for (const Eigen::Isometry3d& start : starts) {
    if (std::any_of(tried.begin(), tried.end(),
                    [&](const Eigen::Isometry3d& t) { return deviation(start, t) < same; })) {
      continue;
    }
    tried.push_back(start);
    const AlignmentResult r =
        aligner_.align(reference_->frame(), current_, to_reference * onGround(start, step));
    ++step.starts;
    step.times.registration.solve_ms += r.times.solve_ms;
    answers.push_back({r, reference_->pose() * r.pose});
  }
  // The best fit among the well-conditioned answers (along what a degenerate one cannot observe
  // it kept its start, which is no evidence).
  size_t best = 0;
  for (size_t i = 1; i < answers.size(); ++i) {
    const AlignmentResult& r = answers[i].r;
    if (!r.degenerate && (answers[best].r.degenerate || r.cost < answers[best].r.cost)) best = i;
  }
  // Answers that fit nearly as well as the best (within kClearMargin) the scan cannot tell
  // apart: of those, the prior takes the one nearest the prediction, which must then still beat
  // the prediction's own fit (evidenceSupports()). Rejecting them all instead kept the
  // prediction where every answer, a fraction of a degree apart, lay 0.6 m from it and fitted a
  // quarter better (a VLP-16 at the end of a circular corner: four scans kept turning, 12.9 %
  // drift).
  if (!answers[best].r.degenerate) {
    const size_t winner = best;
    for (size_t i = 0; i < answers.size(); ++i) {
      const AlignmentResult& r = answers[i].r;
      if (!r.degenerate && (1.0 - kClearMargin) * r.cost <= answers[winner].r.cost &&
          deviation(answers[i].pose, predicted) < deviation(answers[best].pose, predicted)) {
        best = i;
      }
    }
  }
  bool supported = evidenceSupports(answers, best, predicted, likely, prediction_cost);
  if (!supported && best != 0 && !answers[best].r.degenerate && !isWeak(answers, answers[best])) {
    // Each answer but the first was registered in the frame deskewed for another motion, which
    // smears a sweep by the difference: a robot that began to turn on the spot at 150 deg/s,
    // its scans deskewed as standing still, had answers 15 deg into the turn fit at 0.6-0.9 of
    // the prediction's cost, all rejected, and the turn was lost. Deskewed with its own motion,
    // as the prediction's cost was evaluated with its own, the best answer is weighed again.
    // Not on a weak scan, whose answer keeps its start along what it cannot observe and, deskewed
    // with the motion that start implies, fits it better (an open road's VLP-16 drive: 3.2 %
    // drift, 9.4 % with weak scans weighed again).
    if (const std::optional<AlignmentResult> r = deskewed_as(answers[best].pose)) {
      answers.push_back({*r, reference_->pose() * r->pose});
      if (!r->degenerate &&
          evidenceSupports(answers, answers.size() - 1, predicted, likely, prediction_cost)) {
        best = answers.size() - 1;
        supported = true;
      }
    }
  }
  if (!supported) {
    keepPrediction(predicted, step.registration);
    step.rejected = true;
    return predicted;
  }
  step.alternative = best != 0;
  step.convincing = answers[best].r.cost < (1.0 - kConvincing) * prediction_cost;
  step.registration = answers[best].r;
  return answers[best].pose;
}

Eigen::Isometry3d LidarOdometry::searchUnobserved(const Eigen::Isometry3d& first, double dt,
                                                  OdometryStep& step) {
  // A registration that cannot observe a direction keeps the prediction along it, which is
  // right only where the prediction is: a drive that starts at speed on a road with nothing but
  // kerbs along it was predicted at rest for ever, though a pole passed every few seconds. Where
  // the velocity is uncertain along such directions (motion_cov_), the scan's fit against the
  // previous scan is evaluated over a grid of motions spread over two standard deviations of
  // the velocity along them. The previous scan, not the reference: the reference stays where
  // the stalled estimate left it, and a pole entering the view is in no older scan. Structure
  // that the registration could not use (a pole 1.5 m from where the prediction put it, in
  // levels too coarse to keep a cell of it) makes a clear minimum there. Only the fit is
  // evaluated, no Gauss-Newton: on such scans the finest level alone wanders (kerbs pulled
  // registrations tens of degrees round).
  const OdometryParams& o = params_.odometry;
  const double rs = params_.registration.solver.rotation_scale;
  // Too few cells (solver.min_cells) make any fit noise: an HDL-32 scan of the open road kept
  // 10, whose best fit lay 2.5 m backwards.
  if (!(o.max_speed > 0.0) || previous_points_.empty() || current_.levels().empty() ||
      static_cast<int>(current_.levels().front().cells.size()) <
          params_.registration.solver.min_cells) {
    return first;
  }
  const AlignmentResult& first_r = step.registration;
  const Eigen::Matrix3d a = leftToBody(first_r.pose, rs);
  const Eigen::Matrix3d c = a * planarScaled(first_r.covariance, rs) * a.transpose();
  // The unobserved subspace (vehicle frame), and the velocity's spread over one interval
  // within it.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ec(0.5 * (c + c.transpose()));
  Eigen::Matrix3d unobserved = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (ec.eigenvalues()(i) > kUnobservedThreshold)
      unobserved += ec.eigenvectors().col(i) * ec.eigenvectors().col(i).transpose();
  }
  if (unobserved.trace() < 0.5) return first;
  // Translations only: what the search finds is a few cells of structure (a pole), which pins
  // where the vehicle is but not how it turned (that takes two such features apart), and
  // searching the heading too found minima of a few cells' noise that set yaw rates of 10 deg/s.
  const Eigen::Matrix3d prior = dt * dt * motion_cov_.bottomRightCorner<3, 3>();
  const Eigen::DiagonalMatrix<double, 3> translation(1.0, 1.0, 0.0);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> ep(translation * unobserved * prior * unobserved *
                                                    translation);
  const double spacing = current_.levels().front().grid.resolution();
  // Search axes: the prior's two widest directions within the unobserved subspace, where two
  // standard deviations reach beyond the basin of the coarsest level (kSearchBasin cells): a
  // prediction closer than that to the truth leaves the registration nothing to find.
  std::vector<Eigen::Vector3d> axes;
  std::vector<double> ranges;
  for (int i = 2; i >= 1; --i) {
    const double range = 2.0 * std::sqrt(std::max(0.0, ep.eigenvalues()(i)));
    if (range > kSearchBasin * spacing) {
      axes.push_back(ep.eigenvectors().col(i));
      ranges.push_back(range);
    }
  }
  if (axes.empty()) return first;
  // The previous scan as a reference, deskewed as it was registered.
  {
    Stopwatch w;
    const SweepMotion motion = previous_times_.size() == previous_points_.size()
                                   ? SweepMotion(previous_times_, previous_velocity_)
                                   : SweepMotion();
    const DloParams& reg = params_.registration;
    previous_frame_.build(previous_points_, motion, reg.grid, reg.selection, reg.includeGround(),
                          FrameUse::kReferenceOnly);
    step.times.registration.grid_ms += w.elapsedMs();
  }
  if (previous_frame_.empty()) return first;
  // Steps along each axis, the whole grid within kSearchResiduals: wider spacing for wider
  // ranges or more cells.
  const double poses =
      std::max(kMinSearchPoses,
               kSearchResiduals / std::max<double>(1.0, current_.levels().front().cells.size()));
  const double per_axis = axes.size() == 1 ? poses : std::sqrt(poses);
  std::vector<int> steps;
  std::vector<double> spacings;
  for (double range : ranges) {
    const int n = std::max(1, std::min(static_cast<int>(std::ceil(range / spacing)),
                                       static_cast<int>(0.5 * (per_axis - 1.0))));
    steps.push_back(n);
    spacings.push_back(range / n);
  }
  // The motion since the previous scan as the registration has it, moved by d (vehicle frame).
  const Eigen::Isometry3d relative = last_pose_.inverse() * first;
  const auto moved = [&](const Eigen::Vector3d& d) {
    return relative * expSE3(planarTwist(d, rs));
  };
  const double start_cost = aligner_.cost(previous_frame_, current_, relative);
  std::vector<std::pair<Eigen::Vector3d, double>> grid = {{Eigen::Vector3d::Zero(), start_cost}};
  const int n1 = steps.size() > 1 ? steps[1] : 0;
  for (int i = -steps[0]; i <= steps[0]; ++i) {
    for (int j = -n1; j <= n1; ++j) {
      if (i == 0 && j == 0) continue;
      Eigen::Vector3d d = i * spacings[0] * axes[0];
      if (axes.size() > 1) d += j * spacings[1] * axes[1];
      grid.emplace_back(d, aligner_.cost(previous_frame_, current_, moved(d)));
      ++step.search_starts;
    }
  }
  const auto lowest = std::min_element(
      grid.begin(), grid.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
  const Eigen::Vector3d best = lowest->first;
  const double best_cost = lowest->second;
  // The minimum must be the only one: the rings of a sparse sensor on flat ground repeat every
  // few metres and fit as well one ring further (an HDL-32 registered 2.5 m backwards per scan
  // otherwise); a pole fits in one place. Outside the basin around the best pose nothing may fit
  // nearly as well.
  double second = start_cost;
  for (const auto& [d, cost] : grid) {
    if ((d - best).norm() > kSearchBasin * spacing) second = std::min(second, cost);
  }
  if (!(best_cost < (1.0 - kClearMargin) * second)) return first;
  // The farther from the prediction (in standard deviations m of the velocity), the more a
  // motion must lower the cost: by kClearMargin near it, up to half at two standard deviations
  // and beyond.
  const Eigen::Matrix3d prior_info = (prior + 1e-9 * Eigen::Matrix3d::Identity()).inverse();
  const double m2 = best.dot(prior_info * best);
  const double demanded = kClearMargin + (1.0 - kClearMargin) * std::min(0.5, m2 / 8.0);
  if (!(best_cost < (1.0 - demanded) * start_cost)) return first;
  // Registered against the reference from there: what the scan observes is refined, the rest
  // stays where the search put it (the registration keeps its start along what it cannot see).
  const Eigen::Isometry3d to_reference = reference_->pose().inverse();
  const Eigen::Isometry3d found = last_pose_ * moved(best);
  const AlignmentResult r =
      aligner_.align(reference_->frame(), current_, to_reference * onGround(found, step));
  step.times.registration.solve_ms += r.times.solve_ms;
  step.searched = true;
  backfillRun(axes, spacings, best, dt, step);
  step.search_motion = logSE3(moved(best)) / dt;
  step.registration = r;
  // The search measured the searched directions to within its spacing: the covariance says so
  // (the motion filter, and the pose graph's edge, would otherwise learn nothing from it).
  Eigen::Matrix3d searched = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d keep = Eigen::Matrix3d::Identity();
  for (size_t k = 0; k < axes.size(); ++k) {
    searched += spacings[k] * spacings[k] * axes[k] * axes[k].transpose();
    keep -= axes[k] * axes[k].transpose();
  }
  const Eigen::Matrix3d a_r = leftToBody(r.pose, rs);
  Eigen::Matrix3d cb = a_r * planarScaled(r.covariance, rs) * a_r.transpose();
  cb = keep * cb * keep + searched;
  setPlanarScaled(a_r.inverse() * cb * a_r.inverse().transpose(), rs, step.registration.covariance);
  // The velocity along the searched directions is now known to the grid's spacing per interval.
  Eigen::Matrix<double, 6, 6> k6 = Eigen::Matrix<double, 6, 6>::Identity();
  k6.bottomRightCorner<3, 3>() = keep;
  motion_cov_ = k6 * motion_cov_ * k6.transpose();
  motion_cov_.bottomRightCorner<3, 3>() += searched / (dt * dt);
  return reference_->pose() * r.pose;
}

std::optional<Eigen::Isometry3d> LidarOdometry::searchTurn(const Eigen::Isometry3d& first,
                                                           double dt) const {
  const double reach = params_.odometry.max_yaw_rate * kDeg * dt;
  const HeightFrame& reference = reference_->frame();
  const int level =
      static_cast<int>(std::min(reference.levels().size(), current_.levels().size())) - 1;
  if (!(reach > 0.0) || level < 1) return std::nullopt;
  const Eigen::Isometry3d to_reference = reference_->pose().inverse();
  const Eigen::Isometry3d since = last_pose_.inverse() * first;
  const double turned = yawPitchRoll(since.linear()).x();
  double best_cost = aligner_.cost(reference, current_, to_reference * first, level);
  std::optional<Eigen::Isometry3d> best;
  const int n = static_cast<int>(std::ceil(2.0 * reach / kTurnStep));
  for (int k = -n; k <= n; ++k) {
    const double a = k * kTurnStep;
    if (std::abs(k) < kTurnBasinSteps || std::abs(turned + a) > reach) continue;
    const Eigen::Isometry3d pose = first * Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ());
    const double c = aligner_.cost(reference, current_, to_reference * pose, level);
    if (c < best_cost) {
      best_cost = c;
      best = pose;
    }
  }
  return best;
}

void LidarOdometry::backfillRun(const std::vector<Eigen::Vector3d>& axes,
                                const std::vector<double>& spacings, const Eigen::Vector3d& found,
                                double dt, OdometryStep& step) const {
  if (unobserved_run_.empty()) return;
  const size_t n = unobserved_run_.size();
  // The velocity's prior over this interval: the search runs before the scan updates it.
  const Eigen::Matrix3d velocity_prior = motion_cov_.bottomRightCorner<3, 3>();
  // Per axis, the share of the velocity change that each interval of the run takes: the
  // velocity's variance along the axis then over its variance now (for a random walk, the
  // covariance of the two over the variance of the later).
  std::vector<Eigen::Vector3d> shift(n, Eigen::Vector3d::Zero());  // vehicle frame, metres
  std::vector<double> var(n);
  for (size_t k = 0; k < axes.size(); ++k) {
    const Eigen::Vector3d& a = axes[k];
    const double now = a.dot(velocity_prior * a);
    const double moved = a.dot(found);
    // The search measures to within its grid's spacing: a change of a step or two is what its
    // quantisation alone can make, and spread over a long run it would move every scan of it
    // (an open road's 66 scans between poles, 1.5 % too fast, were made 4.6 % too slow by a
    // one-step change). Only a change the grid resolves is smoothed into the run.
    if (!(now > 0.0) || !(std::abs(moved) > kBackfillSteps * spacings[k])) continue;
    for (size_t i = 0; i < n; ++i) var[i] = a.dot(unobserved_run_[i].velocity_cov * a);
    // Only a run along which the velocity had not been measured before: one search is a single
    // interval's measurement, and where a velocity measured before the run disagrees with it,
    // the search may be the one that is wrong (on an open road a search that found a minimum
    // 0.8 m backwards, which the next scans undid, moved the 74 scans before it by 27 m).
    // Where the velocity was never measured, whatever the search finds is better than the
    // prior's guess (a drive at speed predicted at rest). A variance that fell by more than
    // kMeasuredVarianceDrop from one interval to the next had the velocity measured there.
    bool measured = var.front() < kUnmeasuredShare * now;
    for (size_t i = 0; i + 1 < n && !measured; ++i)
      measured = var[i] > kMeasuredVarianceDrop * var[i + 1];
    if (measured) continue;
    for (size_t i = 0; i < n; ++i) {
      const double w = std::clamp(var[i] / now, 0.0, 1.0);
      shift[i] += w * moved * (unobserved_run_[i].dt / dt) * a;
    }
  }
  if (std::all_of(shift.begin(), shift.end(), [](const Eigen::Vector3d& v) { return v.isZero(); }))
    return;
  step.backfill.resize(n);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    // Planar twist coordinates: x and y are metres; the axes hold no rotation.
    total += unobserved_run_[i].rotation * Eigen::Vector3d(shift[i].x(), shift[i].y(), 0.0);
    step.backfill[i] = total;
  }
}

void LidarOdometry::predictMotionCovariance(double dt) {
  // Constant velocity: the pose's error grows by the velocity's; the velocity takes a random
  // walk whose steps have the acceleration limits (10 m/s^2 and 120 deg/s^2 by default) as two
  // standard deviations.
  const OdometryParams& o = params_.odometry;
  const double rs = params_.registration.solver.rotation_scale;
  Eigen::Matrix<double, 6, 6> f = Eigen::Matrix<double, 6, 6>::Identity();
  f.topRightCorner<3, 3>() = dt * Eigen::Matrix3d::Identity();
  motion_cov_ = f * motion_cov_ * f.transpose();
  const double a = 0.5 * o.max_acceleration * dt;
  const double w = 0.5 * o.max_yaw_acceleration * kDeg * rs * dt;
  motion_cov_.diagonal().tail<3>() += Eigen::Vector3d(a * a, a * a, w * w);
}

Eigen::Vector3d LidarOdometry::updateMotionCovariance(const AlignmentResult& r, double dt) {
  const double rs = params_.registration.solver.rotation_scale;
  const Eigen::Matrix3d c = planarScaled(r.covariance, rs);
  const Eigen::Matrix3d a = leftToBody(r.pose, rs);
  const Eigen::Matrix3d s = motion_cov_.topLeftCorner<3, 3>() + a * c * a.transpose() +
                            1e-12 * Eigen::Matrix3d::Identity();
  const Eigen::Matrix<double, 6, 3> gain = motion_cov_.leftCols<3>() * s.inverse();
  Eigen::Vector3d velocity_gain = Eigen::Vector3d::Ones();
  if (dt > 0.0 && dt < 1.0) {
    for (int i = 0; i < 3; ++i) velocity_gain(i) = std::clamp(gain(3 + i, i) * dt, 0.0, 1.0);
  }
  motion_cov_ -= gain * motion_cov_.topRows<3>();
  motion_cov_ = 0.5 * (motion_cov_ + motion_cov_.transpose()).eval();
  return velocity_gain;
}

bool LidarOdometry::evidenceSupports(const std::vector<Answer>& answers, size_t best,
                                     const Eigen::Isometry3d& predicted,
                                     const std::vector<Eigen::Isometry3d>& likely,
                                     double prediction_cost) const {
  const Answer& winner = answers[best];
  if (winner.r.degenerate) return false;
  const bool weak = isWeak(answers, winner);
  // A soft prior: an answer d from the prediction must fit the scan better than the prediction
  // itself, its cost lower by the fraction (d / D)^2 (D = kPriorScale, a quarter of it for a
  // weak scan, times one more for each scan in a row that kept the prediction), and never by
  // more than half: an answer that halves the prediction's cost is
  // believed however far it lies (a robot that turns on the spot at 90 deg/s from rest is 9 deg
  // from its prediction; a truck overtaking close by pulled registrations 1.7 m away while
  // lowering the cost by at most a quarter).
  // Each scan that kept the prediction makes it older and less certain: the prior widens with
  // the run, as the disagreement bound does.
  const double widen = (weak ? 0.25 : 1.0) * (1.0 + rejected_run_);
  // Besides the prediction (the velocity filtered over two intervals, its change held to the
  // acceleration limits) the prior holds two motions as likely (`likely`): the last scan's
  // measured motion continued, and the prediction with its yaw rate stopped. They part from the
  // prediction where the yaw rate steps faster than the limits follow, as robots, handheld rigs
  // and brisk drivers make it do; an answer's distance from the prior is its distance from the
  // nearest of the three. A robot that began to turn on the spot at 90 deg/s between two sweeps
  // registered 6.8 deg at 0.51 of the prediction's cost (not convincing), and the limited
  // velocity predicted 1.3 deg per scan: the next three scans' answers, 7.9 deg from three
  // starts at 0.52 of the prediction's cost, were rejected, and the heading ended the turn
  // 23 deg off (ATE 1.18 m over 300 scans; 0.05 m with the motion continued). One that stopped
  // a 120 deg/s turn as a sweep began had the next scan's answer, 2.5 deg of turn at 0.57 of
  // the prediction's cost 13 deg away, rejected: 19 deg off (ATE 0.54 m; 0.06 m with the turn
  // stopped). Only for a scan that is not weak: a weak scan's answer keeps its start along what
  // it cannot observe, so one started from a likely motion ends near it whatever the scan
  // shows (an open road's HDL-32 scans of 66 cells: 2.0 % drift, 15 % with them).
  double from_prior = deviation(winner.pose, predicted);
  if (!weak) {
    for (const Eigen::Isometry3d& l : likely)
      from_prior = std::min(from_prior, deviation(winner.pose, l));
  }
  double d = from_prior / (kPriorScale * widen);
  // Against keyframes, an answer that brings the scan nearer to where the newest keyframe was
  // taken than the prediction is has its translation weighed on a quarter of that scale
  // (kTowardsKeyframeScale): 0.35 m must halve the cost. Two scans from one place share what
  // the sensor makes of the world (where each ring crosses a kerb, the occlusion shadows), and on
  // a street uniform along its length that fits better at the keyframe than the street fits at
  // the true motion: a car at 8.7 m/s registered 0.8 m behind its prediction, onto the keyframe,
  // and stayed there for 18 scans while it drove 14 m (docs/benchmarks.md). The cost cannot
  // tell; the speed can, which a car changes by 0.7 m/s per scan even braking hard.
  if (reference_->madeOfKeyframes()) {
    const Eigen::Vector3d anchor = reference_->pose().translation();
    if ((winner.pose.translation() - anchor).norm() < (predicted.translation() - anchor).norm()) {
      const double moved = (winner.pose.translation() - predicted.translation()).norm();
      d = std::max(d, moved / (kTowardsKeyframeScale * widen));
    }
  }
  const double demanded = weak ? std::min(1.0, d * d) : std::min(kConvincing, d * d);
  return winner.r.cost < (1.0 - demanded) * prediction_cost;
}

bool LidarOdometry::isWeak(const std::vector<Answer>& answers, const Answer& winner) const {
  // A scan that some start registered as degenerate constrains little: its best fit is weak
  // evidence, and the prior is held to more firmly (a street ending in an open field pulled
  // the heading by 2 deg otherwise).
  const double same = kSameAnswer * params_.odometry.max_prior_deviation;
  return std::any_of(answers.begin(), answers.end(), [&](const Answer& a) {
    return a.r.degenerate && deviation(a.pose, winner.pose) > same;
  });
}

double LidarOdometry::deviation(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) const {
  const Eigen::Isometry3d c = a.inverse() * b;
  return std::max(c.translation().norm(), params_.registration.solver.rotation_scale *
                                              Eigen::AngleAxisd(c.linear()).angle());
}

const std::vector<float>& LidarOdometry::sweepTimes(const PointCloud& points,
                                                    const std::vector<float>& measured,
                                                    OdometryStep& step) {
  const double period = sweepPeriod(params_.odometry, period_);
  const std::vector<float>& t =
      pointTimesFor(points, measured, params_.odometry, period, estimated_times_, step.point_times);
  if (step.point_times == PointTimeSource::kFromOrder ||
      step.point_times == PointTimeSource::kFromParams) {
    step.sweep_period = period;
  }
  return t;
}

double sweepPeriod(const OdometryParams& o, const SweepPeriodEstimate& scans) {
  return o.sweep_period > 0.0 ? o.sweep_period : scans.period(kDefaultSweepPeriod);
}

const std::vector<float>& pointTimesFor(const PointCloud& points,
                                        const std::vector<float>& measured, const OdometryParams& o,
                                        double period, std::vector<float>& buffer,
                                        PointTimeSource& source) {
  static const std::vector<float> kNoTimes;
  source = PointTimeSource::kNone;
  if (o.deskew == 0 || points.empty()) return kNoTimes;
  if (measured.size() == points.size()) {
    source = PointTimeSource::kMeasured;
    return measured;
  }
  if (o.estimate_times == 0) return kNoTimes;
  SweepTimingParams timing;
  timing.period = period;
  timing.direction = o.sweep_direction;
  timing.start_azimuth_deg = o.sweep_start_azimuth;
  timing.stamp_phase = o.sweep_stamp;
  const SweepTimingEstimate e = estimateSweepTimes(points, timing, buffer);
  source = e.from_order ? PointTimeSource::kFromOrder : PointTimeSource::kFromParams;
  return buffer;
}

bool LidarOdometry::disagrees(const Eigen::Isometry3d& predicted,
                              const Eigen::Isometry3d& pose) const {
  const OdometryParams& o = params_.odometry;
  // Only against a velocity measured past the start (whose first scans, registered without a
  // velocity or against an undeskewed scan, legitimately jump by 0.3 m), and not for ever:
  // after a run of rejections it is the prediction that has probably gone wrong.
  if (!(o.max_prior_deviation > 0.0) || settled_updates_ < kSettledVelocityUpdates ||
      rejected_run_ >= o.max_rejected_scans) {
    return false;
  }
  const Eigen::Isometry3d c = predicted.inverse() * pose;
  const double turn =
      params_.registration.solver.rotation_scale * Eigen::AngleAxisd(c.linear()).angle();
  // Each rejection makes the prediction older, so the bound widens with the run: a vehicle
  // entering a turn during a run is caught again before the prediction has lagged into another
  // basin (sparse drives ended in a runaway spin otherwise). The heading's bound widens four
  // times slower: the yaw rate is the better part of a prediction, and the wrong basins of
  // sparse scans are mostly a few degrees off (a 6.6 deg jump accepted after three rejections
  // broke an HDL-32 drive).
  const double k = rejected_run_;
  return c.translation().norm() > o.max_prior_deviation * (1.0 + k) ||
         turn > o.max_prior_deviation * (1.0 + 0.25 * k);
}

Vector6d LidarOdometry::limitAcceleration(const Vector6d& measured, double dt) const {
  // A wrong registration that slips through becomes a pose error; without this it also
  // became a velocity error, and every later prediction started from it (a simulated VLP-16
  // drive spun up to 60 m/s and 60 deg/s and never recovered).
  const OdometryParams& o = params_.odometry;
  Vector6d v = measured;
  if (o.max_acceleration > 0.0) {
    Eigen::Vector2d dv = v.head<2>() - velocity_.head<2>();
    const double most = o.max_acceleration * dt;
    if (dv.norm() > most) dv *= most / dv.norm();
    v.head<2>() = velocity_.head<2>() + dv;
  }
  if (o.max_yaw_acceleration > 0.0) {
    const double most = o.max_yaw_acceleration * kDeg * dt;
    v(5) = velocity_(5) + std::clamp(v(5) - velocity_(5), -most, most);
  }
  return v;
}

void LidarOdometry::keepPrediction(const Eigen::Isometry3d& predicted, AlignmentResult& r) const {
  r.pose = reference_->pose().inverse() * predicted;
  r.degenerate = true;
  r.covariance = Matrix6d::Identity() * kUnobservedVariance;
}

Vector6d LidarOdometry::carried(const Vector6d& v) const {
  // Levelled, z, roll and pitch are measured from the ground on every scan, to hundredths of a
  // degree from scan to scan: their rates are carried too, and deskew the sweep (over a crest
  // the pitch turns by 0.6 deg within a sweep at 10 m/s; deskewed without it, the simulated
  // 20 % hills' scans lagged the truth by half a sweep: 0.24 m in height and 0.7 deg in pitch
  // within 60 m, against 0.02 m and 0.2 deg). Otherwise only the planar motion (x, y, yaw) is
  // carried: the paper's 3-DoF odometry does not measure the rest, and 6-DoF's per-scan
  // estimates of it are noisy.
  return levelling() ? v : planar(v);
}

bool LidarOdometry::levelling() const {
  return params_.odometry.levelling == 1 && params_.registration.solver.dof == 3;
}

Eigen::Isometry3d LidarOdometry::onGround(const Eigen::Isometry3d& pose, OdometryStep& step) {
  step.levelled = false;
  if (!levelling() || !reference_->ready() || current_.empty()) return pose;
  Stopwatch watch;
  const size_t k = groundLevel(current_);
  if (!ground_fitted_) {
    fitGroundSurface(current_.levels()[k].grid, GroundSurfaceParams(), ground_);
    ground_fitted_ = true;
  }
  Eigen::Isometry3d out = pose;
  if (ground_.found && k < reference_->frame().levels().size()) {
    const GroundAlignment g = alignToGround(reference_->frame().levels()[k].grid, ground_.cells,
                                            reference_->pose().inverse() * pose,
                                            params_.registration.solver.rotation_scale);
    if (g.aligned) out = reference_->pose() * g.pose;
    step.levelled = g.aligned;
    step.ground_covariance = g.covariance;
  }
  step.times.ground_ms += watch.elapsedMs();
  return out;
}

bool LidarOdometry::hasStructure() const {
  // A scan cut to a handful of points would make a keyframe, and the anchor of the local map,
  // that later scans cannot be registered against; a bare field is not worth one either. Once
  // structure returns, the distance rule makes the keyframe at once.
  return static_cast<int>(current_.levels().front().cells.size()) >=
         params_.registration.solver.min_cells;
}

bool LidarOdometry::needsKeyframe(const Eigen::Isometry3d& pose, const AlignmentResult& r) const {
  const Eigen::Isometry3d delta = last_keyframe_pose_.inverse() * pose;
  const OdometryParams& o = params_.odometry;
  if (delta.translation().norm() >= o.keyframe_distance) return true;
  if (Eigen::AngleAxisd(delta.linear()).angle() >= o.keyframe_angle * kDeg) return true;
  // A poor fit means the reference no longer describes the surroundings, which only a new
  // keyframe changes when keyframes make the reference (1, 2); a degenerate fit would make a
  // poor keyframe, so it waits for structure to return. Frame to frame and with the scan map
  // the reference moves on every scan anyway, and sparse fits, above the bound nearly always,
  // made a keyframe of nearly every scan: a graph node, a cloud and a loop search each.
  if (!reference_->madeOfKeyframes()) return false;
  if (!(o.keyframe_max_rms > 0.0)) return false;
  if (r.degenerate || r.rms_height_error <= o.keyframe_max_rms) return false;
  // Optionally, poor compared with what a new keyframe gives here as well: a fit against one
  // made from the scan just before is as good as this reference gets, and where that is
  // already above the bound (real HDL-64 city scans fit 0.33-0.41 m RMS right after a keyframe,
  // Ouster-like 128-beam sweeps likewise) every scan becomes a keyframe otherwise.
  if (o.keyframe_rms_ratio <= 0.0 || fresh_fits_.empty()) return true;
  std::vector<double> fits(fresh_fits_.begin(), fresh_fits_.end());
  std::nth_element(fits.begin(), fits.begin() + fits.size() / 2, fits.end());
  return r.rms_height_error > o.keyframe_rms_ratio * fits[fits.size() / 2];
}

void LidarOdometry::addKeyframe(const Eigen::Isometry3d& pose, const PointCloud& points,
                                const SweepMotion& motion, OdometryStep& step) {
  WeightedCloud fine;
  decimate(points, motion, fine, step.keyframe_cloud);
  step.new_keyframe = true;
  last_keyframe_pose_ = pose;
  awaiting_fresh_fit_ = true;
  reference_->addKeyframe(pose, std::move(fine));
}

void LidarOdometry::decimate(const PointCloud& points, const SweepMotion& motion,
                             WeightedCloud& fine, WeightedCloud& coarse) {
  const OdometryParams& o = params_.odometry;
  nearPoints(points, motion, o.map_range, near_);
  fine.clear();
  // Only the keyframe map (reference keyframe or keyframe_map) reads `fine`: frame to frame and
  // with the scan map (sparse sensors) it is not made at all.
  if (reference_->madeOfKeyframes()) {
    if (o.keyframe_voxel > 0.0) {
      fine = voxelise(near_, o.keyframe_voxel);
      coarse = voxelise(fine, o.map_voxel);
      return;
    }
    // No decimation: at 0.05 m an HDL-64 sweep keeps 100k of its 129k points, and hashing them
    // cost more than the rest of a keyframe; rasterising the 30% more points costs less.
    fine = unitWeights(near_);
  }
  coarse = voxelise(near_, o.map_voxel);
}

void LidarOdometry::redoFirstKeyframe(OdometryStep& step) {
  // The first two scans were registered raw, so the velocity they give is consistent; with it
  // the first keyframe can now be deskewed like every later scan.
  const PointCloud first = dlo::deskew(first_points_, first_times_, velocity_);
  WeightedCloud fine;
  decimate(first, SweepMotion(), fine, step.first_keyframe_cloud);
  reference_->redoFirstScan(first, last_pose_, std::move(fine));
  first_points_ = PointCloud();
  first_times_ = std::vector<float>();
}

}  // namespace dlo
