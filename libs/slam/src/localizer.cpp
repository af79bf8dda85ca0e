#include "dlo/slam/localizer.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "dlo/core/deskew.h"
#include "dlo/core/ground_alignment.h"
#include "dlo/core/ground_surface.h"
#include "dlo/core/range_message.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/stage_times.h"
#include "dlo/core/units.h"
#include "dlo/files/error.h"
#include "dlo/formats/height_map_centroids.h"
#include "dlo/formats/png_file.h"
#include "dlo/mrpt/pose_conversion.h"
#include "dlo/slam/lidar_odometry.h"
#include "search_basins.h"

namespace dlo {

namespace {

/// The odometry that bridges between registrations against the map: cells at their centres, on
/// the paper's 400 x 400 cells at most. Points at their centroids (selection.centroid_levels)
/// cost the odometry twice the time, and on the localisation benchmark's HDL-64 drives they
/// localised fewer scans (96.5 % against 99.5 % on seed 1): the map decides where the vehicle
/// is, the odometry only carries it over. Likewise dlo-slam's 600 cells (60 m), which cut its
/// drift over hundreds of metres, cost 1.6-2 times the time per scan, and an HDL-64 patrol
/// (seed 3) localised 91.5 % of its scans with them against 99.0 % with 400.
SlamParams bridgingOdometry(SlamParams slam) {
  slam.registration.selection.centroid_levels = 0;
  const HeightGridParams paper;
  slam.registration.grid.cols = std::min(slam.registration.grid.cols, paper.cols);
  slam.registration.grid.rows = std::min(slam.registration.grid.rows, paper.rows);
  return slam;
}

/// Localised scans whose median RMS sets what a tracked registration may reach.
constexpr size_t kRecentFits = 20;
/// Scans after a re-localisation that jumped away from the odometry's pose that must be
/// localised before the jump is reported.
constexpr int kConfirmations = 2;
/// With bridge_only, the velocity that carries a localised vehicle is measured over the last this
/// many intervals between localised scans (so many + 1 localised in a row stop the odometry).
/// Over one interval, each registration's error (centimetres, tenths of a degree) goes into the
/// next prediction and the sweep's deskewing, and the poses oscillated about the path. Over a
/// turn of constant rate, the twist over several intervals is the same as over one.
constexpr size_t kVelocityIntervals = 3;
/// The localised scans that measure the map's velocity for a second start (Localizer::
/// mapVelocity()) lie at most kMaxAgeIntervals intervals before the current scan, the newest at
/// most kMaxGapIntervals, and span two intervals at least (kMinSpanIntervals, with the
/// intervals' jitter).
constexpr double kMaxAgeIntervals = kVelocityIntervals + 2.5;
constexpr double kMaxGapIntervals = 2.5;
constexpr double kMinSpanIntervals = 1.5;
/// A registration's variance along what it cannot observe (DirectAligner), at least.
constexpr double kUnobservedFloor = 1e5;
/// A search needs this many distinct places that fit at all to judge the best against them.
constexpr size_t kMinBasins = 5;

bool distinct(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const Eigen::Isometry3d d = a.inverse() * b;
  return d.translation().head<2>().norm() > kDistinctBasin ||
         Eigen::AngleAxisd(d.linear()).angle() > kDistinctBasinAngle;
}

/// The registration parameters of `slam` on a square grid of `cells` cells of `resolution`,
/// with levels up to about 1.6 m (the basin a prediction or a search start must fall in).
DloParams gridFor(const SlamParams& slam, double resolution, int cells, int max_levels) {
  DloParams p = slam.registration;
  p.grid.resolution = resolution;
  p.grid.cols = p.grid.rows = cells;
  int levels = 1;
  while (levels < max_levels && resolution * (1 << levels) <= 1.6 + 1e-9 &&
         (cells >> levels) >= 8) {
    ++levels;
  }
  p.grid.levels = levels;
  return p;
}
}  // namespace

std::string LocalizerParams::validate() const {
  if (!(cells >= 16 && cells <= 4000))
    return outOfRange("localizer.cells", cells, "16 to 4000 cells");
  if (!(rebuild_distance > 0.0))
    return outOfRange("localizer.rebuild_distance", rebuild_distance, "a positive distance");
  if (!(min_inliers > 0.0 && min_inliers <= 1.0))
    return outOfRange("localizer.min_inliers", min_inliers, "(0, 1]");
  if (!(rms_ratio >= 1.0)) return outOfRange("localizer.rms_ratio", rms_ratio, ">= 1");
  if (!(max_rms > 0.0)) return outOfRange("localizer.max_rms", max_rms, "a positive height");
  if (!(max_correction > 0.0))
    return outOfRange("localizer.max_correction", max_correction, "a positive distance");
  if (!(tracking_basin > 0.0))
    return outOfRange("localizer.tracking_basin", tracking_basin, "a positive cell size");
  if (!(lost_after >= 1)) return outOfRange("localizer.lost_after", lost_after, ">= 1 scan");
  if (!(search_every >= 1)) return outOfRange("localizer.search_every", search_every, ">= 1 scan");
  if (!(search_spacing > 0.0))
    return outOfRange("localizer.search_spacing", search_spacing, "a positive distance");
  if (!(search_yaw_step_deg > 0.0 && search_yaw_step_deg <= 180.0))
    return outOfRange("localizer.search_yaw_step_deg", search_yaw_step_deg, "(0, 180] degrees");
  if (!(search_contrast >= 1.0))
    return outOfRange("localizer.search_contrast", search_contrast, ">= 1");
  if (!(ambiguity_ratio >= 1.0))
    return outOfRange("localizer.ambiguity_ratio", ambiguity_ratio, ">= 1");
  return {};
}

void centreHeights(PriorMap& map) {
  const std::vector<std::uint8_t>& centroids = map.centroids;
  const size_t cells = static_cast<size_t>(map.cols) * static_cast<size_t>(map.rows);
  if (map.count.size() != cells || map.sum.size() != cells || centroids.size() != 2 * cells) {
    throw std::invalid_argument("centreHeights: the centroids do not match the map's cells");
  }
  std::vector<float> height(cells, 0.0f);
  for (size_t k = 0; k < cells; ++k) {
    if (map.count[k] > 0) height[k] = map.sum[k] / static_cast<float>(map.count[k]);
  }
  const float res = static_cast<float>(map.resolution);
  // The slope at cell k along one axis (`step` cells to the next one, at index i of n), as the
  // registration's gradients take it: central differences of the cells' heights, one-sided
  // beside an empty cell, none between two.
  const auto slope = [&](size_t k, size_t step, int i, int n) {
    const bool below = i > 0 && map.count[k - step] > 0;
    const bool above = i + 1 < n && map.count[k + step] > 0;
    if (below && above) return (height[k + step] - height[k - step]) / (2.0f * res);
    if (above) return (height[k + step] - height[k]) / res;
    if (below) return (height[k] - height[k - step]) / res;
    return 0.0f;
  };
  const size_t row = static_cast<size_t>(map.cols);
  std::vector<float> centred = map.sum;
  for (int iy = 0; iy < map.rows; ++iy) {
    for (int ix = 0; ix < map.cols; ++ix) {
      const size_t k = static_cast<size_t>(iy) * row + static_cast<size_t>(ix);
      if (map.count[k] == 0) continue;
      // The centroid's offset from the centre: the centre lies at minus it.
      const float dx = (HeightMapCentroids::fraction(centroids[2 * k]) - 0.5f) * res;
      const float dy = (HeightMapCentroids::fraction(centroids[2 * k + 1]) - 0.5f) * res;
      const float at_centre =
          height[k] - slope(k, 1, ix, map.cols) * dx - slope(k, row, iy, map.rows) * dy;
      centred[k] = at_centre * static_cast<float>(map.count[k]);
    }
  }
  map.sum = std::move(centred);
  map.heights_at_centres = true;
}

PriorMap loadPriorMap(const std::string& slam_out_dir) {
  const std::string path = (std::filesystem::path(slam_out_dir) / "map.simplemap").string();
  if (!std::filesystem::exists(path)) {
    throw InputError("map '" + path + "' does not exist (--map takes a dlo-slam output folder).");
  }
  mrpt::maps::CSimpleMap simple;
  bool loaded = false;
  try {
    loaded = simple.loadFromFile(path);
  } catch (const std::exception&) {
    loaded = false;
  }
  if (!loaded) throw InputError("map '" + path + "' is not a readable CSimpleMap.");
  PriorMap map;
  for (size_t i = 0; i < simple.size(); ++i) {
    const auto& [pose, frame] = simple.get(i);
    if (!pose || !frame) continue;
    const auto cloud = frame->getObservationByClass<mrpt::obs::CObservationPointCloud>();
    if (!cloud || !cloud->pointcloud || cloud->pointcloud->size() == 0) continue;
    // Points in the observation's sensor frame; the keyframe's vehicle frame is the sensorPose.
    const Eigen::Isometry3d sensor = toIsometry(cloud->sensorPose);
    WeightedCloud points;
    const auto& xs = cloud->pointcloud->getPointsBufferRef_x();
    const auto& ys = cloud->pointcloud->getPointsBufferRef_y();
    const auto& zs = cloud->pointcloud->getPointsBufferRef_z();
    points.reserve(xs.size());
    for (size_t k = 0; k < xs.size(); ++k) {
      const Eigen::Vector3d p = sensor * Eigen::Vector3d(xs[k], ys[k], zs[k]);
      if (!p.allFinite()) continue;
      points.push_back(WeightedPoint{p.cast<float>(), 1u});
    }
    map.poses.push_back(toIsometry(pose->getMeanVal()));
    map.clouds.push_back(std::move(points));
  }
  if (map.size() == 0) throw InputError("map '" + path + "' holds no keyframe with points.");

  const std::string heights = (std::filesystem::path(slam_out_dir) / "heightmap.bin").string();
  mrpt::maps::CHeightGridMap2D grid;
  try {
    mrpt::io::CFileGZInputStream in(heights);
    auto archive = mrpt::serialization::archiveFrom(in);
    archive >> grid;
  } catch (const std::exception&) {
    throw InputError("map '" + heights + "' is missing or not a readable CHeightGridMap2D.");
  }
  map.x_min = grid.getXMin();
  map.y_min = grid.getYMin();
  map.resolution = grid.getResolution();
  map.cols = static_cast<int>(grid.getSizeX());
  map.rows = static_cast<int>(grid.getSizeY());
  map.count.assign(static_cast<size_t>(map.cols) * map.rows, 0);
  map.sum.assign(map.count.size(), 0.0f);
  for (int iy = 0; iy < map.rows; ++iy) {
    for (int ix = 0; ix < map.cols; ++ix) {
      const mrpt::maps::THeightGridmapCell* c = grid.cellByIndex(ix, iy);
      if (!c || c->w == 0) continue;
      const size_t k = static_cast<size_t>(iy) * map.cols + ix;
      map.count[k] = c->w;
      map.sum[k] = c->h * static_cast<float>(c->w);  // h and w are what MRPT serialises
    }
  }
  const std::string centroids =
      (std::filesystem::path(slam_out_dir) / "heightmap_centroids.bin").string();
  if (std::filesystem::exists(centroids)) {
    HeightMapCentroids c = readHeightMapCentroids(centroids);
    if (c.cols != static_cast<std::uint32_t>(map.cols) ||
        c.rows != static_cast<std::uint32_t>(map.rows)) {
      throw InputError("map '" + centroids + "' has " + std::to_string(c.cols) + " x " +
                       std::to_string(c.rows) + " cells, but '" + heights + "' has " +
                       std::to_string(map.cols) + " x " + std::to_string(map.rows) + ".");
    }
    map.centroids = std::move(c.places);
  }
  return map;
}

Localizer::Localizer(PriorMap map, const LocalizerParams& params, const SlamParams& slam)
    : map_(std::move(map)),
      params_(params),
      slam_(slam),
      grid_(gridFor(slam, map_.resolution, params.cells, 6)),
      aligner_(grid_.solver) {
  grid_.selection.block_size = 1;
  // Where the sensor profile places a scan's cells at the centroids of their points
  // (selection.centroid_levels, HeightFrame::placeCellsOnCentroids()), the map's heights are
  // moved to their cells' centres, where its window is read: both sides are then compared where
  // they were measured. Otherwise, or for a map without its centroids, both sides are compared
  // at their cells' centres.
  if (grid_.selection.centroid_levels > 0 && !map_.centroids.empty() && !map_.heights_at_centres) {
    centreHeights(map_);
  }
  map_.centroids.clear();
  map_.centroids.shrink_to_fit();
  if (!map_.heights_at_centres) grid_.selection.centroid_levels = 0;
  while (tracking_levels_ < grid_.grid.levels &&
         map_.resolution * (1 << tracking_levels_) <= params_.tracking_basin + 1e-9) {
    ++tracking_levels_;
  }
}

void Localizer::setInitialPose(const Eigen::Isometry3d& pose) {
  tracking_ = true;
  last_pose_ = pose;
}

LocalizationStep Localizer::process(double time, const PointCloud& points,
                                    const std::vector<float>& point_times) {
  return processScan(time, points, point_times, nullptr, nullptr);
}

LocalizationStep Localizer::process(double time, PointCloud&& points,
                                    std::vector<float>&& point_times) {
  return processScan(time, points, point_times, &points, &point_times);
}

LocalizationStep Localizer::processScan(double time, const PointCloud& points,
                                        const std::vector<float>& point_times, PointCloud* owned,
                                        std::vector<float>* owned_times) {
  Stopwatch watch;
  LocalizationStep step;
  step.time = time;
  const double dt = scans_ > 0 ? time - last_time_ : 0.0;
  period_.add(time);
  // With bridge_only, while the map localises every scan, the localised poses carry the vehicle
  // to the next scan (at 10 Hz a constant velocity is right to centimetres, and the map corrects
  // them): the odometry, which costs as much as the registration against the map, does not run.
  // It runs before the first fix and from a scan that this prediction did not carry (see below)
  // until the map has localised enough scans in a row to measure the velocity again: its
  // motion bridges the scans the map does not localise.
  bool from_map = params_.bridge_only && tracking_ && probation_ == 0 &&
                  recent_poses_.size() > kVelocityIntervals && dt > 0.0 && dt < 1.0;
  const bool map_start = from_map;
  Eigen::Isometry3d moved = expSE3(velocity_ * std::max(dt, 0.0));
  const std::vector<float>* times = nullptr;
  // The odometry on this scan: its motion since the last scan, its velocity and point times. A
  // stopped odometry starts afresh, from the previous scan where one was kept (so that it
  // measures this scan's motion), else from this one (the velocity carries the pose).
  const auto runOdometry = [&] {
    if (!odometry_) {
      odometry_ = std::make_unique<LidarOdometry>(bridgingOdometry(slam_));
      if (!previous_points_.empty())
        last_odometry_ = odometry_->process(previous_time_, previous_points_, previous_times_).pose;
    }
    const OdometryStep odometry = odometry_->process(time, points, point_times);
    step.odometry = true;
    if (odometry_->frames() > 1) {
      moved = last_odometry_.inverse() * odometry.pose;
      velocity_ = odometry_->velocity();
    }
    last_odometry_ = odometry.pose;
    times = &odometry_->lastPointTimes();  // estimated once, there
  };
  const auto build = [&] {
    const SweepMotion motion =
        !times->empty() && scans_ > 0 ? SweepMotion(*times, velocity_) : SweepMotion();
    current_.build(points, motion, grid_.grid, grid_.selection, grid_.includeGround(),
                   FrameUse::kCurrentOnly);
    ground_fitted_ = false;
  };
  if (from_map) {
    odometry_.reset();
    PointTimeSource source = PointTimeSource::kNone;
    times = &pointTimesFor(points, point_times, slam_.odometry,
                           sweepPeriod(slam_.odometry, period_), estimated_times_, source);
  } else {
    runOdometry();
  }
  build();

  bool believed = false;
  bool on_probation = probation_ > 0;
  // Tracked from `from`: believed when the fit is and it moved the pose at most max_correction.
  const auto trackFrom = [&](const Eigen::Isometry3d& from, LocalizationStep& s) {
    const bool ok = track(from, trackingBound(), s, Start::kPrediction);
    s.correction = (s.pose.translation() - from.translation()).norm();
    return ok && s.correction <= params_.max_correction;
  };
  if (tracking_) {
    Eigen::Isometry3d predicted = last_pose_ * moved;
    if (on_probation) fallback_ = fallback_ * moved;
    believed = trackFrom(predicted, step);
    if (!believed && from_map) {
      // The map's velocity did not carry the vehicle to this scan (a turn began or ended, a
      // hard stop): the odometry, started again from the previous scan, measures the motion, and
      // the scan, deskewed with it, is registered again from there.
      from_map = false;
      recent_poses_.clear();
      runOdometry();
      build();
      predicted = last_pose_ * moved;
      believed = trackFrom(predicted, step);
    }
    // Registered again from `start`, the scan deskewed with `velocity`; kept if believed, else
    // the scan goes back to the odometry's deskewing.
    const auto retryFrom = [&](const Eigen::Isometry3d& start, const Vector6d& velocity) {
      const Vector6d odometry_velocity = velocity_;
      velocity_ = velocity;
      build();
      LocalizationStep retry = step;
      if (trackFrom(start, retry)) {
        step = retry;
        predicted = start;
        return true;
      }
      velocity_ = odometry_velocity;
      build();
      return false;
    };
    // The odometry's motion did not carry the vehicle to a believable fit: the motion the map
    // measured over its last localised scans is a second start, and the scan is deskewed with
    // it. A sparse odometry can jump: a simulated VLP-16 patrol's moved 4.7 m in one scan after
    // a turn on the spot, and its next scans were lost until a search; at the end of a turn a
    // VLP-16 odometry moved 1.5-1.7 m per scan for eight scans where the vehicle moved 0.8, and
    // the map's fits, right to a decimetre, lay 0.8-1.1 m from its predictions. The localised
    // scans need not be in a row (the odometry's first wrong prediction breaks the row), but
    // they span two intervals at least: over one, each fit's error goes into the velocity whole
    // (a patrol's turn on the spot, started from one interval's motion, was believed 0.5 m off).
    // Not when the map's velocity was this scan's first start: that start has failed already.
    Eigen::Isometry3d by_map;
    Vector6d map_velocity;
    const bool measured =
        !believed && dt > 0.0 && dt < 1.0 && mapVelocity(time, dt, map_velocity, by_map);
    if (measured && !map_start) believed = retryFrom(by_map, map_velocity);
    // Nor the map's motion: the vehicle may have stopped (a turn on the spot that ends stops its
    // rotation within a scan, where an odometry started at the turn's end jumped 0.4-0.6 m per
    // scan). The previous scan's pose, localised, is a last start, tried where the map's motion
    // over the interval moves less than a believable correction, so that the two starts lie
    // within reach of each other (at speed, a start at rest is only a wrong basin's).
    if (!believed && measured && localised_.back().first == last_time_ &&
        (map_velocity.head<3>() * dt).norm() <= params_.max_correction) {
      believed = retryFrom(localised_.back().second, Vector6d::Zero());
    }
    if (!believed && on_probation) {
      // The place a search jumped to does not hold: back to the odometry's own path.
      predicted = fallback_;
      probation_ = 0;
    }
    if (!believed) step.pose = predicted;
    if (believed && on_probation) --probation_;
  }
  const bool lost = !tracking_ || unlocalised_run_ + 1 >= params_.lost_after;
  // A sweep with per-point times is searched for once the odometry has measured a velocity to
  // deskew it with (the second scan): undeskewed, the first fix lay 0.4 m off at 10 m/s.
  const bool deskewed = times->empty() || scans_ > 0;
  if (!believed && lost && deskewed && since_search_ >= params_.search_every) {
    step.searched = true;
    since_search_ = 0;
    Eigen::Isometry3d found;
    double fit = 0.0;
    if (search(tracking_ ? &step.pose : nullptr, found, fit)) {
      LocalizationStep verified = step;
      recent_rms_.assign(1, fit);
      if (track(found, trackingBound(), verified, Start::kFound)) {
        // A jump away from where the odometry has the vehicle is believed once the next scans
        // confirm it (a wrong place found in a corridor failed on the next scan); until then
        // its scans are not reported as localised.
        if (tracking_ && distinct(step.pose, verified.pose)) {
          fallback_ = step.pose;
          probation_ = kConfirmations;
          on_probation = true;
        }
        step = verified;
        step.searched = true;
        step.found = true;
        believed = true;
      }
    }
  }

  if (believed) {
    // Localised scans in a row measure the velocity once the odometry no longer runs (its own,
    // where it runs, is kept). A re-localisation starts them again: the poses before lie
    // elsewhere.
    if (step.found) {
      recent_poses_.clear();
      localised_.clear();
    }
    recent_poses_.emplace_back(time, step.pose);
    localised_.emplace_back(time, step.pose);
    if (localised_.size() > kVelocityIntervals + 1) localised_.pop_front();
    if (recent_poses_.size() > kVelocityIntervals + 1) recent_poses_.pop_front();
    if (from_map) velocity_ = recentVelocity();
    tracking_ = true;
    fixed_ = true;
    unlocalised_run_ = 0;
    step.confidence = on_probation && probation_ > 0
                          ? 0.0
                          : std::clamp(step.inliers * (1.0 - step.rms / params_.max_rms), 0.0, 1.0);
    recent_rms_.push_back(step.rms);
    if (recent_rms_.size() > kRecentFits) recent_rms_.erase(recent_rms_.begin());
  } else {
    ++unlocalised_run_;
    recent_poses_.clear();
  }
  // Not localised, the pose is the odometry's from the last fix (dead reckoning).
  if (tracking_) last_pose_ = step.pose;
  ++since_search_;
  ++scans_;
  last_time_ = time;
  // While the odometry is stopped, the scan is kept for it to start from (see runOdometry()).
  if (!odometry_) {
    if (owned != nullptr) {
      // Swapped, not copied (a dense sweep is 1.5 MB): the caller refills the old buffers.
      previous_points_.swap(*owned);
      previous_times_.swap(*owned_times);
    } else {
      previous_points_ = points;
      previous_times_ = point_times;
    }
    previous_time_ = time;
  } else {
    previous_points_.clear();
  }
  conditioned_fix_ = believed && !fit_degenerate_;
  step.localised = believed && !(on_probation && probation_ > 0);
  step.fixed = fixed_;
  step.ms = watch.elapsedMs();
  return step;
}

Vector6d Localizer::recentVelocity() const {
  const auto& [t0, p0] = recent_poses_.front();
  const auto& [t1, p1] = recent_poses_.back();
  return logSE3(p0.inverse() * p1) / (t1 - t0);
}

bool Localizer::mapVelocity(double time, double dt, Vector6d& velocity,
                            Eigen::Isometry3d& start) const {
  auto oldest = localised_.begin();
  while (oldest != localised_.end() && oldest->first < time - kMaxAgeIntervals * dt) ++oldest;
  if (oldest == localised_.end()) return false;
  const auto& [t0, p0] = *oldest;
  const auto& [t1, p1] = localised_.back();
  if (t1 - t0 < kMinSpanIntervals * dt || time - t1 > kMaxGapIntervals * dt) return false;
  velocity = logSE3(p0.inverse() * p1) / (t1 - t0);
  start = p1 * expSE3(velocity * (time - t1));
  return true;
}

double Localizer::trackingBound() const {
  if (recent_rms_.empty()) return params_.max_rms;
  std::vector<double> v = recent_rms_;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return std::min(params_.max_rms, params_.rms_ratio * v[v.size() / 2]);
}

Localizer::Fit Localizer::fit(const Eigen::Isometry3d& guess, Start start) {
  Fit f;
  if (current_.empty() || !referenceAround(guess)) return f;
  // The odometry's motion carries z, roll and pitch from the last levelled pose: only the
  // result is levelled.
  const Eigen::Isometry3d from = start == Start::kPrediction ? guess : levelled(guess);
  const AlignmentResult r = aligner_.align(reference_, current_, reference_pose_.inverse() * from,
                                           start == Start::kSearch ? 0 : tracking_levels_);
  const double selected = static_cast<double>(current_.levels().front().cells.size());
  f.pose = levelled(reference_pose_ * r.pose);
  f.rms = r.rms_height_error;
  f.inliers = selected > 0.0 ? r.cells / selected : 0.0;
  f.cost = r.cost;
  f.degenerate = r.degenerate;
  // A fit that cannot observe one direction of the plane (along a street of straight walls)
  // keeps its start along it, and that start is good when the previous scan was localised by a
  // well-conditioned fit: one interval of the map's own velocity. Directions with the
  // registration's unobserved variance (1e6) counted; never two in a row.
  int unobserved = 0;
  for (int i : {0, 1, 5}) unobserved += r.covariance(i, i) >= kUnobservedFloor;
  const bool carried = start == Start::kPrediction && conditioned_fix_ && unobserved <= 1 &&
                       r.cells >= grid_.solver.min_cells;
  f.believable = (!r.degenerate || carried) && f.inliers >= params_.min_inliers;
  return f;
}

bool Localizer::track(const Eigen::Isometry3d& guess, double rms_bound, LocalizationStep& step,
                      Start start) {
  const Fit f = fit(guess, start);
  step.rms = f.rms;
  step.inliers = f.inliers;
  fit_degenerate_ = f.degenerate;
  const bool ok = f.believable && f.rms <= rms_bound;
  if (ok) step.pose = f.pose;
  return ok;
}

bool Localizer::referenceAround(const Eigen::Isometry3d& pose, bool force) {
  const Eigen::Vector2d at = pose.translation().head<2>();
  if (!force && reference_ready_ &&
      (at - reference_pose_.translation().head<2>()).norm() < params_.rebuild_distance) {
    return true;
  }
  // The window of the height map centred near the vehicle, its cells on the map's.
  const int n = params_.cells;
  const double res = map_.resolution;
  const long ix0 = std::lround((at.x() - map_.x_min) / res - 0.5 * n);
  const long iy0 = std::lround((at.y() - map_.y_min) / res - 0.5 * n);
  Eigen::Isometry3d window = Eigen::Isometry3d::Identity();
  window.translation() << map_.x_min + (ix0 + 0.5 * n) * res, map_.y_min + (iy0 + 0.5 * n) * res,
      0.0;
  if (!force && reference_ready_ && window.isApprox(reference_pose_)) return true;
  size_t seen = 0;
  const auto fill = [&](std::uint32_t* count, float* sum) {
    for (int r = 0; r < n; ++r) {
      const long iy = iy0 + r;
      if (iy < 0 || iy >= map_.rows) continue;
      for (int c = 0; c < n; ++c) {
        const long ix = ix0 + c;
        if (ix < 0 || ix >= map_.cols) continue;
        const size_t k = static_cast<size_t>(iy) * map_.cols + static_cast<size_t>(ix);
        count[r * n + c] = map_.count[k];
        sum[r * n + c] = map_.sum[k];
        seen += map_.count[k] > 0;
      }
    }
  };
  reference_.build(fill, grid_.grid, grid_.selection, grid_.includeGround(),
                   FrameUse::kReferenceOnly);
  reference_pose_ = window;
  reference_ready_ = seen > 0 && !reference_.empty();
  return reference_ready_;
}

Eigen::Isometry3d Localizer::levelled(const Eigen::Isometry3d& pose) {
  if (!reference_ready_ || current_.empty()) return pose;
  const size_t k = groundLevel(current_);
  if (k >= reference_.levels().size()) return pose;
  if (!ground_fitted_) {
    fitGroundSurface(current_.levels()[k].grid, GroundSurfaceParams(), ground_);
    ground_fitted_ = true;
  }
  if (!ground_.found) return pose;
  const GroundAlignment g =
      alignToGround(reference_.levels()[k].grid, ground_.cells, reference_pose_.inverse() * pose,
                    grid_.solver.rotation_scale);
  return g.aligned ? Eigen::Isometry3d(reference_pose_ * g.pose) : pose;
}

bool Localizer::search(const Eigen::Isometry3d* prediction, Eigen::Isometry3d& found,
                       double& best_rms) {
  if (current_.empty()) return false;
  // Keyframes search_spacing apart, every heading: the vehicle drives where the map's keyframes
  // were made, so one of them lies within a metre or two of it, and one heading within half a
  // step of its own. Each start is registered at full resolution (the pyramid's coarsest level
  // reaches 1.6 m) and scored as tracking scores it: a coarse grid alone ranked the right place
  // nowhere near the top (simulated town: RMS 0.21 at wrong places, where the full resolution
  // separates 0.38 at the right one from 0.74 and more elsewhere).
  std::vector<Fit> basins;  // per distinct place, the best-fitting registration that ended there
  const int yaws = std::max(1, static_cast<int>(std::lround(360.0 / params_.search_yaw_step_deg)));
  std::vector<Eigen::Vector2d> tried;
  for (size_t i = 0; i < map_.size(); ++i) {
    const Eigen::Vector3d at = map_.poses[i].translation();
    if (std::any_of(tried.begin(), tried.end(), [&](const Eigen::Vector2d& t) {
          return (t - at.head<2>()).norm() < params_.search_spacing;
        })) {
      continue;
    }
    tried.push_back(at.head<2>());
    const double heading = yawPitchRoll(map_.poses[i].linear()).x();
    for (int y = 0; y < yaws; ++y) {
      const Eigen::Isometry3d start =
          poseFromXYZYPR(at.x(), at.y(), at.z(), heading + y * 2.0 * M_PI / yaws, 0.0, 0.0);
      const Fit f = fit(start, Start::kSearch);
      if (f.degenerate) continue;
      auto same = std::find_if(basins.begin(), basins.end(),
                               [&](const Fit& b) { return !distinct(b.pose, f.pose); });
      if (same == basins.end()) {
        basins.push_back(f);
      } else if (f.cost < same->cost) {
        *same = f;
      }
    }
  }
  if (basins.size() < kMinBasins) return false;
  const auto best = std::min_element(basins.begin(), basins.end(),
                                     [](const Fit& a, const Fit& b) { return a.cost < b.cost; });
  if (!best->believable) return false;
  // The right place fits clearly better than the map's other places do, and no other place
  // nearly as well (parallel streets, a repeated facade): otherwise the next scans search
  // again. Compared by cost, which counts the cells that found no map: a sparse VLP-16 sweep
  // fits at 0.8-0.9 m RMS everywhere, but finds the map with 80 % of its cells at the right
  // place and 35-45 % elsewhere. Simulated HDL-64 second days: the right place costs 0.024-0.030,
  // the next distinct place 1.5-2.3 times more, the median place 2.6-3.5 times more.
  std::vector<double> costs;
  for (const Fit& b : basins) costs.push_back(b.cost);
  std::nth_element(costs.begin(), costs.begin() + costs.size() / 2, costs.end());
  if (!(best->cost * params_.search_contrast <= costs[costs.size() / 2])) return false;
  for (const Fit& b : basins) {
    if (distinct(b.pose, best->pose) && b.cost < best->cost * params_.ambiguity_ratio) {
      return false;
    }
  }
  // While tracking, the odometry's prediction stands unless the map clearly prefers the place
  // found: the fit where the prediction stands, unmoved, against the fit there (a corridor
  // whose scans fit poorly for a few metres found a place 2.7 m along the road otherwise; after
  // a kidnapping the prediction fits badly).
  if (prediction && distinct(*prediction, best->pose)) {
    referenceAround(*prediction, true);
    const double at_prediction =
        aligner_.cost(reference_, current_, reference_pose_.inverse() * *prediction);
    referenceAround(best->pose, true);
    const double at_best =
        aligner_.cost(reference_, current_, reference_pose_.inverse() * best->pose);
    if (!(at_best * params_.ambiguity_ratio <= at_prediction)) return false;
  }
  best_rms = best->rms;
  found = best->pose;
  return true;
}

void writeLocalizationImage(const PriorMap& map, const std::vector<LocalizationStep>& steps,
                            const std::string& png) {
  // Bounds: the keyframes and their surroundings, and every pose drawn.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = Eigen::Vector2d::Constant(std::numeric_limits<double>::lowest());
  const auto extend = [&](const Eigen::Vector2d& p, double margin) {
    lo = lo.cwiseMin(p - Eigen::Vector2d::Constant(margin));
    hi = hi.cwiseMax(p + Eigen::Vector2d::Constant(margin));
  };
  for (const Eigen::Isometry3d& k : map.poses) extend(k.translation().head<2>(), 30.0);
  for (const LocalizationStep& s : steps) {
    if (s.fixed) extend(s.pose.translation().head<2>(), 5.0);
  }
  const double span = std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const double res = std::max(0.25, span / 4000.0);
  const int cols = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / res)));
  const int rows = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / res)));
  const auto pixel = [&](const Eigen::Vector3d& p) {
    return cv::Point(static_cast<int>((p.x() - lo.x()) / res),
                     rows - 1 - static_cast<int>((p.y() - lo.y()) / res));
  };
  // The highest point of each pixel, relative to the keyframe below it.
  cv::Mat height(rows, cols, CV_32F, cv::Scalar(-1e9f));
  for (size_t i = 0; i < map.size(); ++i) {
    const double ground = map.poses[i].translation().z();
    for (const WeightedPoint& wp : map.clouds[i]) {
      const Eigen::Vector3d p = map.poses[i] * wp.p.cast<double>();
      const cv::Point px = pixel(p);
      if (px.x < 0 || px.y < 0 || px.x >= cols || px.y >= rows) continue;
      float& h = height.at<float>(px);
      h = std::max(h, static_cast<float>(p.z() - ground));
    }
  }
  cv::Mat image(rows, cols, CV_8UC3, cv::Scalar(255, 255, 255));
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const float h = height.at<float>(r, c);
      if (h < -1e8f) continue;
      // Ground (about -2 m below a roof sensor) light grey, 3 m above it black.
      const double t = std::clamp((h + 2.0) / 3.0, 0.0, 1.0);
      const auto v = static_cast<unsigned char>(220.0 - 200.0 * t);
      image.at<cv::Vec3b>(r, c) = cv::Vec3b(v, v, v);
    }
  }
  for (const Eigen::Isometry3d& k : map.poses)
    cv::circle(image, pixel(k.translation()), 1, cv::Scalar(255, 80, 0), cv::FILLED);
  for (const LocalizationStep& s : steps) {
    if (!s.fixed) continue;
    cv::circle(image, pixel(s.pose.translation()), 2,
               s.localised ? cv::Scalar(0, 170, 0) : cv::Scalar(0, 0, 230), cv::FILLED);
  }
  writePng(image, png);
}

}  // namespace dlo
