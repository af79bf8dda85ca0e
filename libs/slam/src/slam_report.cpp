#include "dlo/slam/slam_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

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

/// report.json keeps the keys in the order written, the order users and scripts know.
using Json = nlohmann::ordered_json;

Json stats(const std::vector<double>& v) {
  return {{"median", percentile(v, 0.5)}, {"p95", percentile(v, 0.95)}};
}

/// A segment length for the text of drift_segment_lengths: "100", "12.5".
std::string lengthText(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", metres);
  return text;
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
    lengths << (i ? ", " : "") << lengthText(d_after.per_length[i].length) << " m";
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
  Json report;
  report["input"] = input;
  report["frames"] = c.frames;
  report["keyframes"] = map.keyframes.size();
  report["ms_per_frame"] = stats(t.total);
  report["stages_ms"] = {{"deskew", stats(t.deskew)},       {"grid", stats(t.grid)},
                         {"gradients", stats(t.gradients)}, {"selection", stats(t.selection)},
                         {"solve", stats(t.solve)},         {"keyframe", stats(t.keyframe)},
                         {"local_map", stats(t.local_map)}, {"ground", stats(t.ground)},
                         {"loop_closure", stats(t.loop)}};
  report["loop_closures"] = {
      {"accepted", c.loops_accepted},     {"rejected", c.loops_rejected},
      {"optimisations", c.optimisations}, {"already_consistent", c.loops_consistent},
      {"tracked", c.loops_tracked},       {"tracked_then_searched", c.loops_untracked}};
  // The verdict on every candidate (capped), so that a user can see why a loop did not close.
  constexpr size_t kMaxCandidates = 500;
  Json candidates = Json::array();
  for (size_t i = 0; i < map.loop_candidates.size() && i < kMaxCandidates; ++i) {
    const LoopCandidate& l = map.loop_candidates[i];
    candidates.push_back({{"from", l.from},
                          {"to", l.to},
                          {"accepted", l.accepted},
                          {"tracked", l.tracked},
                          {"reason", l.reason}});
  }
  report["loop_candidates"] = std::move(candidates);
  report["degenerate_frames"] = c.degenerate_frames;
  report["prediction_disagreements"] = {{"decided_by_other_starts", c.multi_start_frames},
                                        {"other_start_won", c.alternative_frames},
                                        {"prediction_kept", c.prediction_kept_frames}};
  // Scans registered again from a heading that fitted the coarsest level better (the turn
  // search), and those where that registration fitted better than the first.
  report["turn_searches"] = {{"frames", c.turn_searched_frames}, {"found", c.turn_found_frames}};
  // Scans whose registration contradicted the prediction, deskewed with other yaw rates (the
  // sweep's own rate), and those where one of them fitted best.
  report["deskew_rate_searches"] = {{"frames", c.rate_searched_frames},
                                    {"found", c.rate_found_frames}};
  // Degenerate registrations along whose unobserved direction the prediction was uncertain
  // (an unmeasured velocity): searched along it, and those where a start found the pose.
  report["unobserved_searches"] = {{"frames", c.searched_frames},
                                   {"found", c.search_found_frames},
                                   {"backfilled_frames", c.backfilled_frames}};
  // How each scan was deskewed: with the input's per-point times, with times estimated from
  // the azimuths (spin start and direction read off the point order, or from the
  // odometry.sweep_* keys), or not at all (deskewing off).
  report["deskew"] = {
      {"measured_times", c.times_measured},
      {"estimated_times_from_point_order", c.times_from_order},
      {"estimated_times_from_config", c.times_from_params},
      {"not_deskewed", c.frames - c.times_measured - c.times_from_order - c.times_from_params}};
  // The revolution period the estimated times spanned: odometry.sweep_period, or (0, the
  // default) read off the scans' timestamps (dlo::SweepPeriodEstimate).
  if (c.sweep_period > 0.0) {
    report["deskew"]["sweep_period_s"] = c.sweep_period;
    report["deskew"]["sweep_period_from"] =
        pipeline.params().odometry.sweep_period > 0.0 ? "odometry.sweep_period" : "scan timestamps";
  }
  // What the odometry estimates: "3d-levelled" (x, y, yaw registered, z, roll and pitch from
  // the ground, odometry.levelling), "3-dof" (the paper's planar odometry) or "6-dof" (the
  // joint solve, solver.dof = 6); and how many scans found a ground to level on.
  const SlamParams& p = pipeline.params();
  const char* dof = p.registration.solver.dof == 6 ? "6-dof"
                    : p.odometry.levelling == 1    ? "3d-levelled"
                                                   : "3-dof";
  report["estimation"] = {{"dof", dof}, {"levelled_frames", c.levelled_frames}};
  report["sensor_profile"] = {{"name", profile.name}, {"chosen_because", profile.reason}};
  // The heights the grids keep (odometry.visibility_ceiling): what the sensor sees everywhere
  // on the grid, from its height and its highest beam.
  const VisibilityCeiling& vc = profile.ceiling;
  report["visibility_ceiling"] = {{"applied", vc.applied},
                                  {"grid_max_z_m", vc.max_z},
                                  {"sensor_height_m", vc.sensor_height},
                                  {"top_elevation_deg", std::isfinite(vc.top_elevation_deg)
                                                            ? nlohmann::json(vc.top_elevation_deg)
                                                            : nlohmann::json(nullptr)}};
  report["empty_frames"] = c.empty_frames;
  // Peak of the whole run so far (processing and export); the samples show how resident memory
  // evolved with the scans and how much of it the keyframes hold.
  report["peak_memory_mb"] = peakResidentMemoryMb();
  const std::vector<MemorySample>& mem = pipeline.memorySamples();
  Json samples = Json::array();
  for (const MemorySample& m : mem) {
    samples.push_back({{"frame", m.frame},
                       {"resident_mb", m.resident_mb},
                       {"keyframes", m.keyframes},
                       {"keyframe_mb", m.keyframe_mb},
                       {"spilled_mb", m.spilled_mb}});
  }
  report["memory"] = {{"unexplained_growth_kb_per_frame", unexplainedGrowthKbPerFrame(mem)},
                      {"samples", std::move(samples)}};
  report["interrupted"] = interrupted;
  report["input_error"] = input_error.empty() ? Json(nullptr) : Json(input_error);
  if (accuracy) {
    const SlamAccuracy& a = *accuracy;
    report["accuracy"] = {{"alignment", "umeyama-se3"},
                          {"matched_poses", a.matched},
                          {"before_loop_closure",
                           {{"ate_rmse_m", a.ate_rmse_before},
                            {"ate_max_m", a.ate_max_before},
                            {"final_error_m", a.final_error_before},
                            {"drift_percent", a.drift_percent_before},
                            {"drift_deg_per_100m", a.drift_deg_per_100m_before}}},
                          {"after_loop_closure",
                           {{"ate_rmse_m", a.ate_rmse_after},
                            {"ate_max_m", a.ate_max_after},
                            {"final_error_m", a.final_error_after},
                            {"drift_percent", a.drift_percent_after},
                            {"drift_deg_per_100m", a.drift_deg_per_100m_after}}},
                          {"drift_segment_lengths", a.drift_lengths}};
  }
  report["config"] = config_ini;
  // Paths and INI text are the user's bytes: invalid UTF-8 is replaced rather than thrown on.
  return report.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace dlo
