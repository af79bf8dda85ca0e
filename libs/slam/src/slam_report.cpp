#include "dlo/slam/slam_report.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "dlo/core/json_text.h"
#include "dlo/metrics/absolute_trajectory_error.h"
#include "dlo/metrics/kitti_drift.h"
#include "dlo/metrics/timestamp_matching.h"
#include "dlo/slam/process_memory.h"

namespace dlo {

namespace {

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t i = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size()))) - 1;
  return v[std::min(i, v.size() - 1)];
}

std::string number(double x) {
  return jsonNumber(x, 6);
}

std::string quoted(const std::string& text) {
  return jsonString(text);
}

std::string stats(const std::vector<double>& v) {
  return "{\"median\": " + number(percentile(v, 0.5)) +
         ", \"p95\": " + number(percentile(v, 0.95)) + "}";
}

metrics::Trajectory trajectoryOf(const SlamMap& map, bool optimised) {
  metrics::Trajectory t;
  for (size_t i = 0; i < map.frames.size(); ++i) {
    t.times.push_back(map.frames[i].time);
    t.poses.push_back(optimised ? map.framePose(i) : map.frames[i].odometry);
  }
  return t;
}

}  // namespace

metrics::Trajectory slamTrajectory(const SlamMap& map) {
  return trajectoryOf(map, true);
}
metrics::Trajectory odometryTrajectory(const SlamMap& map) {
  return trajectoryOf(map, false);
}

SlamAccuracy evaluateAgainst(const SlamMap& map, const metrics::Trajectory& ground_truth) {
  constexpr double kMaxDt = 0.005;
  SlamAccuracy a;
  const auto [after, ref] = metrics::matchedTrajectories(slamTrajectory(map), ground_truth, kMaxDt);
  const auto [before, ref2] =
      metrics::matchedTrajectories(odometryTrajectory(map), ground_truth, kMaxDt);
  if (after.size() < 3 || before.size() < 3) {
    throw std::runtime_error("only " + std::to_string(after.size()) +
                             " poses match the ground truth by timestamp (within 5 ms).");
  }
  a.matched = after.size();
  const metrics::AteResult ate_after =
      metrics::absoluteTrajectoryError(after, ref, metrics::Alignment::kUmeyama);
  const metrics::AteResult ate_before =
      metrics::absoluteTrajectoryError(before, ref2, metrics::Alignment::kUmeyama);
  a.ate_rmse_after = ate_after.error.rmse;
  a.ate_max_after = ate_after.error.max;
  a.ate_rmse_before = ate_before.error.rmse;
  a.ate_max_before = ate_before.error.max;
  // The final error in the first pose's frame: how far the run ends from where it should.
  const metrics::AteResult first_after =
      metrics::absoluteTrajectoryError(after, ref, metrics::Alignment::kFirstPose);
  const metrics::AteResult first_before =
      metrics::absoluteTrajectoryError(before, ref2, metrics::Alignment::kFirstPose);
  a.final_error_after =
      ((first_after.transform * after.poses.back()).translation() - ref.poses.back().translation())
          .norm();
  a.final_error_before = ((first_before.transform * before.poses.back()).translation() -
                          ref2.poses.back().translation())
                             .norm();
  const metrics::KittiDriftResult d_after = metrics::kittiDrift(after, ref);
  const metrics::KittiDriftResult d_before = metrics::kittiDrift(before, ref2);
  a.drift_percent_after = d_after.translation_percent;
  a.drift_percent_before = d_before.translation_percent;
  a.drift_deg_per_100m_after = d_after.rotation_deg_per_100m;
  a.drift_deg_per_100m_before = d_before.rotation_deg_per_100m;
  std::ostringstream lengths;
  for (size_t i = 0; i < d_after.per_length.size(); ++i) {
    lengths << (i ? ", " : "") << number(d_after.per_length[i].length) << " m";
  }
  a.drift_lengths = lengths.str();
  return a;
}

std::string slamReportJson(const SlamPipeline& pipeline, const std::string& input,
                           const SensorProfileChoice& profile, const std::string& config_ini,
                           const std::optional<SlamAccuracy>& accuracy, bool interrupted,
                           const std::string& input_error) {
  const PipelineTimings& t = pipeline.timings();
  const PipelineCounters& c = pipeline.counters();
  const SlamMap& map = pipeline.map();
  std::ostringstream o;
  o << "{\n  \"input\": " << quoted(input) << ",\n";
  o << "  \"frames\": " << c.frames << ",\n  \"keyframes\": " << map.keyframes.size() << ",\n";
  o << "  \"ms_per_frame\": " << stats(t.total) << ",\n";
  o << "  \"stages_ms\": {\"deskew\": " << stats(t.deskew) << ", \"grid\": " << stats(t.grid)
    << ", \"gradients\": " << stats(t.gradients) << ", \"selection\": " << stats(t.selection)
    << ", \"solve\": " << stats(t.solve) << ", \"keyframe\": " << stats(t.keyframe)
    << ", \"local_map\": " << stats(t.local_map) << ", \"ground\": " << stats(t.ground)
    << ", \"loop_closure\": " << stats(t.loop) << "},\n";
  o << "  \"loop_closures\": {\"accepted\": " << c.loops_accepted
    << ", \"rejected\": " << c.loops_rejected << ", \"optimisations\": " << c.optimisations
    << ", \"already_consistent\": " << c.loops_consistent << ", \"tracked\": " << c.loops_tracked
    << ", \"tracked_then_searched\": " << c.loops_untracked << "},\n";
  // The verdict on every candidate (capped), so that a user can see why a loop did not close.
  constexpr size_t kMaxCandidates = 500;
  o << "  \"loop_candidates\": [";
  for (size_t i = 0; i < map.loop_candidates.size() && i < kMaxCandidates; ++i) {
    const LoopCandidate& l = map.loop_candidates[i];
    o << (i ? ",\n    " : "\n    ") << "{\"from\": " << l.from << ", \"to\": " << l.to
      << ", \"accepted\": " << (l.accepted ? "true" : "false")
      << ", \"tracked\": " << (l.tracked ? "true" : "false") << ", \"reason\": " << quoted(l.reason)
      << "}";
  }
  o << "],\n";
  o << "  \"degenerate_frames\": " << c.degenerate_frames << ",\n";
  o << "  \"prediction_disagreements\": {\"decided_by_other_starts\": " << c.multi_start_frames
    << ", \"other_start_won\": " << c.alternative_frames
    << ", \"prediction_kept\": " << c.prediction_kept_frames << "},\n";
  // Degenerate registrations along whose unobserved direction the prediction was uncertain
  // (an unmeasured velocity): searched along it, and those where a start found the pose.
  o << "  \"unobserved_searches\": {\"frames\": " << c.searched_frames
    << ", \"found\": " << c.search_found_frames << "},\n";
  // How each scan was deskewed: with the input's per-point times, with times estimated from
  // the azimuths (spin start and direction read off the point order, or from the
  // odometry.sweep_* keys), or not at all (deskewing off).
  o << "  \"deskew\": {\"measured_times\": " << c.times_measured
    << ", \"estimated_times_from_point_order\": " << c.times_from_order
    << ", \"estimated_times_from_config\": " << c.times_from_params << ", \"not_deskewed\": "
    << c.frames - c.times_measured - c.times_from_order - c.times_from_params << "},\n";
  // What the odometry estimates: "3d-levelled" (x, y, yaw registered, z, roll and pitch from
  // the ground, odometry.levelling), "3-dof" (the paper's planar odometry) or "6-dof" (the
  // joint solve, solver.dof = 6); and how many scans found a ground to level on.
  const SlamParams& p = pipeline.params();
  const char* dof = p.registration.solver.dof == 6 ? "6-dof"
                    : p.odometry.levelling == 1    ? "3d-levelled"
                                                   : "3-dof";
  o << "  \"estimation\": {\"dof\": \"" << dof << "\", \"levelled_frames\": " << c.levelled_frames
    << "},\n";
  o << "  \"sensor_profile\": {\"name\": " << quoted(profile.name)
    << ", \"chosen_because\": " << quoted(profile.reason) << "},\n";
  o << "  \"empty_frames\": " << c.empty_frames << ",\n";
  // Peak of the whole run so far (processing and export); the samples show how resident memory
  // evolved with the scans and how much of it the keyframes hold.
  o << "  \"peak_memory_mb\": " << number(peakResidentMemoryMb()) << ",\n";
  const std::vector<MemorySample>& mem = pipeline.memorySamples();
  o << "  \"memory\": {\"unexplained_growth_kb_per_frame\": "
    << number(unexplainedGrowthKbPerFrame(mem)) << ", \"samples\": [";
  for (size_t i = 0; i < mem.size(); ++i) {
    o << (i ? ",\n    " : "\n    ") << "{\"frame\": " << mem[i].frame
      << ", \"resident_mb\": " << number(mem[i].resident_mb)
      << ", \"keyframes\": " << mem[i].keyframes
      << ", \"keyframe_mb\": " << number(mem[i].keyframe_mb)
      << ", \"spilled_mb\": " << number(mem[i].spilled_mb) << "}";
  }
  o << "]},\n";
  o << "  \"interrupted\": " << (interrupted ? "true" : "false") << ",\n";
  o << "  \"input_error\": " << (input_error.empty() ? "null" : quoted(input_error)) << ",\n";
  if (accuracy) {
    const SlamAccuracy& a = *accuracy;
    o << "  \"accuracy\": {\"alignment\": \"umeyama-se3\", \"matched_poses\": " << a.matched
      << ",\n    \"before_loop_closure\": {\"ate_rmse_m\": " << number(a.ate_rmse_before)
      << ", \"ate_max_m\": " << number(a.ate_max_before)
      << ", \"final_error_m\": " << number(a.final_error_before)
      << ", \"drift_percent\": " << number(a.drift_percent_before)
      << ", \"drift_deg_per_100m\": " << number(a.drift_deg_per_100m_before) << "},\n"
      << "    \"after_loop_closure\": {\"ate_rmse_m\": " << number(a.ate_rmse_after)
      << ", \"ate_max_m\": " << number(a.ate_max_after)
      << ", \"final_error_m\": " << number(a.final_error_after)
      << ", \"drift_percent\": " << number(a.drift_percent_after)
      << ", \"drift_deg_per_100m\": " << number(a.drift_deg_per_100m_after) << "},\n"
      << "    \"drift_segment_lengths\": " << quoted(a.drift_lengths) << "},\n";
  }
  o << "  \"config\": " << quoted(config_ini) << "\n}\n";
  return o.str();
}

}  // namespace dlo
