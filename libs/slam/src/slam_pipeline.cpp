#include "dlo/slam/slam_pipeline.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "dlo/core/units.h"
#include "dlo/slam/keyframe_graph.h"
#include "dlo/slam/process_memory.h"

namespace dlo {

namespace {
/// Keyframes to wait after an accepted loop before looking again: consecutive keyframes would
/// mostly re-add the same constraint.
constexpr int kLoopCooldown = 3;
/// A candidate within this many keyframes of the last accepted loop, on both of its sides, is
/// the same revisit going on: it is verified from its guess first (LoopSearch::kFromGuess).
constexpr int kTrackedSpan = 2 * kLoopCooldown;
/// Two verified loops agree (loop.confirm) when they put the vehicle within half the width of a
/// lattice basin of each other (the loop closer's basins are 1.5 m and 5 deg apart; the distance
/// is loop.max_disagreement, 0.75 m by default).
constexpr double kAgreementAngle = 2.5 * kDeg;  // radians
}  // namespace

SlamPipeline::SlamPipeline(const SlamParams& params)
    : params_(params), odometry_(params), loops_(params) {}

void SlamPipeline::process(double time, const PointCloud& points,
                           const std::vector<float>& point_times) {
  Stopwatch total;
  const OdometryStep step = odometry_.process(time, points, point_times);
  applyBackfill(step);
  Eigen::Isometry3d pose = step.pose;
  pose.translation() += odometry_shift_;
  ++counters_.frames;
  if (!step.registered && counters_.frames > 1) ++counters_.empty_frames;
  if (step.registered && step.registration.degenerate) ++counters_.degenerate_frames;
  if (step.starts > 1) ++counters_.multi_start_frames;
  if (step.alternative) ++counters_.alternative_frames;
  if (step.rejected) ++counters_.prediction_kept_frames;
  if (step.turn_searched) ++counters_.turn_searched_frames;
  if (step.turn_found) ++counters_.turn_found_frames;
  if (step.rate_searched) ++counters_.rate_searched_frames;
  if (step.rate_found) ++counters_.rate_found_frames;
  if (step.levelled) ++counters_.levelled_frames;
  if (step.search_starts > 0) ++counters_.searched_frames;
  if (step.searched) ++counters_.search_found_frames;
  switch (step.point_times) {
    case PointTimeSource::kMeasured:
      ++counters_.times_measured;
      break;
    case PointTimeSource::kFromOrder:
      ++counters_.times_from_order;
      break;
    case PointTimeSource::kFromParams:
      ++counters_.times_from_params;
      break;
    case PointTimeSource::kNone:
      break;
  }
  if (step.sweep_period > 0.0) counters_.sweep_period = step.sweep_period;
  travelled_ += (last_odometry_.inverse() * pose).translation().norm();
  last_odometry_ = pose;

  if (!step.first_keyframe_cloud.empty() && !map_.keyframes.empty()) {
    Keyframe& first = map_.keyframes.front();
    first.cloud = step.first_keyframe_cloud;
    first.spilled = false;  // its old slot in the spill file is left unused
    spillOldKeyframes();
  }
  Stopwatch loop_watch;
  if (step.new_keyframe || map_.keyframes.empty()) addKeyframe(time, step, pose);
  const double loop_ms = loop_watch.elapsedMs();
  // Timed with this scan (total), as the cache misses it saves the next one would have been.
  if (step.new_keyframe) odometry_.warmCaches();

  FramePose f;
  f.time = time;
  f.keyframe = static_cast<int>(map_.keyframes.size()) - 1;
  f.relative = kf_odometry_.back().inverse() * pose;
  f.odometry = pose;
  f.degenerate = step.registered && step.registration.degenerate;
  f.rms_height_error = step.registration.rms_height_error;
  map_.frames.push_back(f);

  timings_.total.push_back(total.elapsedMs());
  timings_.deskew.push_back(step.times.deskew_ms);
  timings_.grid.push_back(step.times.registration.grid_ms);
  timings_.gradients.push_back(step.times.registration.gradients_ms);
  timings_.selection.push_back(step.times.registration.selection_ms);
  timings_.solve.push_back(step.times.registration.solve_ms);
  timings_.keyframe.push_back(step.times.keyframe_ms);
  timings_.local_map.push_back(step.times.local_map_ms);
  timings_.ground.push_back(step.times.ground_ms);
  timings_.loop.push_back(loop_ms);
  if (counters_.frames == 1 || counters_.frames % kMemorySampleInterval == 0) sampleMemory();
}

void SlamPipeline::sampleMemory() {
  if (!memory_.empty() && memory_.back().frame == counters_.frames) return;
#if defined(__GLIBC__)
  // Scans of different sizes come and go every frame; glibc keeps the freed heap pages (its
  // mmap threshold rises after the first large frees), so resident memory crept up by about
  // 17 KiB per scan on a 500-sweep HDL-64 run without any live data behind it. Handing the free
  // pages back here (once every kMemorySampleInterval scans) keeps a long run's footprint to
  // what it holds: 2-6 KiB per scan more than its keyframes on the same run (frame poses,
  // timings, the pose graph), and the samples honest.
  malloc_trim(0);
#endif
  MemorySample m;
  m.frame = counters_.frames;
  m.resident_mb = residentMemoryMb();
  m.keyframes = map_.keyframes.size();
  constexpr double kMb = 1024.0 * 1024.0;
  m.keyframe_mb = static_cast<double>(map_.residentCloudBytes()) / kMb;
  m.spilled_mb = map_.spill ? static_cast<double>(map_.spill->bytes()) / kMb : 0.0;
  memory_.push_back(m);
}

double unexplainedGrowthKbPerFrame(const std::vector<MemorySample>& samples) {
  if (samples.size() < 3) return 0.0;
  double n = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, sxy = 0.0;
  for (size_t i = 1; i < samples.size(); ++i) {
    const double x = static_cast<double>(samples[i].frame);
    const double y = (samples[i].resident_mb - samples[i].keyframe_mb) * 1024.0;
    n += 1.0;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  const double d = n * sxx - sx * sx;
  return d > 0.0 ? (n * sxy - sx * sy) / d : 0.0;
}

void SlamPipeline::applyBackfill(const OdometryStep& step) {
  const size_t n = std::min(step.backfill.size(), map_.frames.size());
  if (n == 0) return;
  const size_t first = map_.frames.size() - n;
  const size_t skipped = step.backfill.size() - n;
  // The keyframes among the moved scans: their odometry poses move with them, and their map
  // poses by the same motion in their own frame (which keeps what loop closures did to them).
  for (size_t i = 0; i < n; ++i) {
    FramePose& f = map_.frames[first + i];
    f.odometry.translation() += step.backfill[skipped + i];
  }
  for (size_t k = map_.keyframes.size(); k-- > 0;) {  // the newest ones, back to the run's start
    Keyframe& kf = map_.keyframes[k];
    if (kf.frame < static_cast<int>(first)) break;
    const Eigen::Isometry3d moved = map_.frames[static_cast<size_t>(kf.frame)].odometry;
    kf.pose = kf.pose * (kf_odometry_[k].inverse() * moved);
    kf_odometry_[k] = moved;
  }
  // Odometry edges that end at a moved keyframe carry the moved motion.
  for (PoseEdge& e : map_.edges) {
    if (e.loop || map_.keyframes[static_cast<size_t>(e.to)].frame < static_cast<int>(first))
      continue;
    e.relative = kf_odometry_[static_cast<size_t>(e.from)].inverse() *
                 kf_odometry_[static_cast<size_t>(e.to)];
  }
  for (size_t i = first; i < map_.frames.size(); ++i) {
    FramePose& f = map_.frames[i];
    f.relative = kf_odometry_[static_cast<size_t>(f.keyframe)].inverse() * f.odometry;
  }
  odometry_shift_ += step.backfill.back();
  last_odometry_ = map_.frames.back().odometry;
  counters_.backfilled_frames += n;
}

void SlamPipeline::addKeyframe(double time, const OdometryStep& step,
                               const Eigen::Isometry3d& pose) {
  Keyframe k;
  k.id = static_cast<int>(map_.keyframes.size());
  k.frame = static_cast<int>(map_.frames.size());
  k.time = time;
  k.cloud = step.keyframe_cloud;
  if (k.id == 0) {
    k.pose = pose;
  } else {
    // Chain from the previous keyframe's (possibly optimised) pose with the odometry motion.
    const Eigen::Isometry3d relative = kf_odometry_.back().inverse() * pose;
    k.pose = map_.keyframes.back().pose * relative;
    PoseEdge e;
    e.from = k.id - 1;
    e.to = k.id;
    e.relative = relative;
    const LoopParams& l = params_.loop;
    e.information = edgeInformation(relative, step.registration.covariance, l.min_sigma_xy,
                                    l.min_sigma_angle * kDeg);
    map_.edges.push_back(e);
  }
  map_.keyframes.push_back(std::move(k));
  spillOldKeyframes();
  kf_odometry_.push_back(pose);
  path_length_.push_back(travelled_);
  if (params_.loop.enabled != 0) searchLoops(static_cast<int>(map_.keyframes.size()) - 1);
}

void SlamPipeline::spillOldKeyframes() {
  const size_t resident = static_cast<size_t>(params_.odometry.resident_keyframes);
  if (resident == 0) return;
  for (size_t i = 0; i + resident < map_.keyframes.size(); ++i) {
    if (!map_.keyframes[i].spilled) map_.spillKeyframeCloud(i);
  }
}

void SlamPipeline::searchLoops(int newest) {
  // A loop waiting for confirmation expires once the revisit has gone on without one.
  if (pending_loop_ && newest - pending_loop_->edge.to > kTrackedSpan) pending_loop_.reset();
  if (newest - last_loop_keyframe_ < kLoopCooldown) return;
  const std::vector<int> candidates = loops_.candidates(map_, newest, path_length_);
  // A place whose lattice search closed nothing is searched again only loop.retry_distance
  // further on (a verification from the guess of a tracked revisit is not held back).
  const bool may_search = path_length_[newest] - last_failed_search_ >= params_.loop.retry_distance;
  bool searched = false;
  // The nearest candidates only: verification costs two registrations each.
  constexpr size_t kMaxTries = 2;
  for (size_t i = 0; i < candidates.size() && i < kMaxTries; ++i) {
    const int from = candidates[i];
    const Eigen::Isometry3d guess =
        map_.keyframes[from].pose.inverse() * map_.keyframes[newest].pose;
    // The revisit whose last loop was accepted (and corrected the graph) goes on: the guess is
    // good, and one registration from it costs a tenth of the lattice search. If it does not
    // pass, the lattice search decides.
    const bool tracked = newest - last_loop_keyframe_ <= kTrackedSpan &&
                         std::abs(from - last_loop_from_) <= kTrackedSpan;
    bool accepted = tracked && tryLoop(from, newest, guess, LoopSearch::kFromGuess).accepted;
    if (!accepted && may_search) {
      searched = true;
      accepted = tryLoop(from, newest, guess).accepted;
    }
    if (accepted) {
      last_loop_keyframe_ = newest;
      last_loop_from_ = from;
      return;
    }
  }
  // While a loop waits, no search counts as failed: the next keyframes search again to confirm
  // it.
  if (searched && !pending_loop_) last_failed_search_ = path_length_[newest];
}

bool SlamPipeline::sameBasin(const PoseEdge& a, const PoseEdge& b) const {
  const auto pose = [this](int k) { return map_.keyframes[static_cast<size_t>(k)].pose; };
  const Eigen::Isometry3d implied =
      pose(b.from).inverse() * pose(a.from) * a.relative * pose(a.to).inverse() * pose(b.to);
  const Eigen::Isometry3d d = implied.inverse() * b.relative;
  return d.translation().norm() <= params_.loop.max_disagreement &&
         Eigen::AngleAxisd(d.linear()).angle() <= kAgreementAngle;
}

LoopCandidate SlamPipeline::tryLoop(int from, int to, const Eigen::Isometry3d& guess,
                                    LoopSearch search) {
  PoseEdge edge;
  LoopCandidate c = loops_.verify(map_, from, to, guess, edge, search);
  if (c.accepted && search == LoopSearch::kLattice && params_.loop.confirm) {
    // The first loop of a revisit stands on one verification, and a repetitive street can pass
    // it in the wrong basin (a simulated HDL-32 lap: 2.5 m along the road, with keyframe
    // submaps). It is added once a later keyframe's own search agrees with it; one that does not
    // agree waits in its place.
    // Independent evidence: no keyframe of either side in common with the waiting loop's (two
    // loops from the same old keyframe 0.8 s apart agreed, both 2.5 m off).
    const int count = static_cast<int>(map_.keyframes.size());
    const std::pair<int, int> from_window = loops_.submapWindow(count, from);
    const std::pair<int, int> to_window = loops_.submapWindow(count, to);
    const auto disjoint = [](const std::pair<int, int>& a, const std::pair<int, int>& b) {
      return a.second < b.first || b.second < a.first;
    };
    if (pending_loop_ && (!disjoint(pending_loop_->from_window, from_window) ||
                          !disjoint(pending_loop_->to_window, to_window))) {
      // Not independent of the waiting loop: neither confirms nor replaces it.
      c.accepted = false;
      c.reason = "awaiting confirmation (shares keyframes with the waiting loop)";
      map_.loop_candidates.push_back(c);
      ++counters_.loops_rejected;
      return c;
    }
    const bool confirmed = pending_loop_ &&
                           std::abs(pending_loop_->edge.from - from) <= kTrackedSpan &&
                           sameBasin(pending_loop_->edge, edge);
    if (!confirmed) {
      c.accepted = false;
      c.reason = pending_loop_ ? "awaiting confirmation (the loop before disagreed)"
                               : "awaiting confirmation by a later keyframe's loop";
      pending_loop_ = PendingLoop{edge, map_.loop_candidates.size(), from_window, to_window};
      map_.loop_candidates.push_back(c);
      ++counters_.loops_rejected;
      return c;
    }
    LoopCandidate& first = map_.loop_candidates[pending_loop_->candidate];
    first.accepted = true;
    first.reason = "accepted (confirmed by keyframe " + std::to_string(to) + "'s loop)";
    --counters_.loops_rejected;
    ++counters_.loops_accepted;
    map_.edges.push_back(pending_loop_->edge);
    pending_loop_.reset();
  }
  map_.loop_candidates.push_back(c);
  if (c.accepted) {
    ++counters_.loops_accepted;
    if (c.tracked) ++counters_.loops_tracked;
    map_.edges.push_back(edge);
    // A loop the graph already satisfies (within twice the edges' standard-deviation floors)
    // would not move it: its edge is kept for the next optimisation, which then runs only when a
    // loop disagrees. On repeated laps of a consistent map this skips most optimisations, whose
    // cost grows with the graph (about 100 ms at 900 keyframes).
    const LoopParams& l = params_.loop;
    const Eigen::Isometry3d now = map_.keyframes[from].pose.inverse() * map_.keyframes[to].pose;
    const Eigen::Isometry3d error = edge.relative.inverse() * now;
    const bool consistent =
        error.translation().norm() <= 2.0 * l.min_sigma_xy &&
        Eigen::AngleAxisd(error.linear()).angle() <= 2.0 * l.min_sigma_angle * kDeg;
    if (consistent) {
      ++counters_.loops_consistent;
    } else {
      optimise();
    }
  } else if (search == LoopSearch::kFromGuess) {
    ++counters_.loops_untracked;  // not a rejection: the lattice search follows
  } else {
    ++counters_.loops_rejected;
  }
  return c;
}

void SlamPipeline::optimise() {
  optimisePoseGraph(map_);
  ++counters_.optimisations;
}

}  // namespace dlo
