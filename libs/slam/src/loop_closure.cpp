#include "dlo/slam/loop_closure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "dlo/core/ground_alignment.h"
#include "dlo/core/units.h"
#include "dlo/slam/keyframe_graph.h"
#include "search_basins.h"

namespace dlo {

namespace {
/// Coarse search for the loop's basin: cell size (m), lattice of start offsets (m, degrees).
constexpr double kSearchResolution = 0.8;
constexpr double kSearchOffsets[] = {-4.0, -2.0, 0.0, 2.0, 4.0};
constexpr double kSearchYaws[] = {-12.0, -6.0, 0.0, 6.0, 12.0};
/// A lattice search's answer may turn the guess at most this far: as far as its starts reach, and
/// half a step beyond (15 deg). An answer farther round left the searched region for an unrelated
/// basin (seen on simulated HDL-32 drives with keyframe submaps: loops accepted 17-39 deg round,
/// 3 to 11 m from the truth, where the heading had drifted less than a degree).
constexpr double kMaxLatticeRotation =
    (kSearchYaws[4] + 0.5 * (kSearchYaws[4] - kSearchYaws[3])) * kDeg;  // radians
/// A different basin whose RMS is within this factor of the best makes the place ambiguous.
constexpr double kAmbiguityRatio = 1.05;
/// Basins of the coarse search refined at full resolution.
constexpr size_t kRefinedBasins = 3;

std::string describe(const char* what, double value, double limit) {
  std::ostringstream s;
  s << what << " " << value << " beyond " << limit;
  return s.str();
}
}  // namespace

LoopCloser::LoopCloser(const SlamParams& params) : params_(params), grid_(params.registration) {
  const LoopParams& l = params.loop;
  const int cells = static_cast<int>(std::lround(l.window / l.resolution));
  grid_.grid.resolution = l.resolution;
  grid_.grid.cols = cells;
  grid_.grid.rows = cells;
  // Keep the coarsest level near 1.6 m whatever the verification resolution.
  int levels = 1;
  while (levels < 6 && l.resolution * (1 << levels) <= 1.6 + 1e-9 && (cells >> levels) >= 8) {
    ++levels;
  }
  grid_.grid.levels = levels;
  grid_.selection.block_size = 1;
  coarse_ = grid_;
  coarse_.grid.resolution = kSearchResolution;
  coarse_.grid.cols = coarse_.grid.rows =
      static_cast<int>(std::lround(l.window / kSearchResolution));
  coarse_.grid.levels = 1;
  if (l.enabled != 0) {
    // The verification's frames take their memory now, once (tens of megabytes at the default
    // window): a fixed working set from the start rather than a step at the first loop.
    const WeightedCloud none;
    const Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    const bool ground = grid_.includeGround();
    ref_.build(none, origin, grid_.grid, grid_.selection, ground);
    cur_.build(none, origin, grid_.grid, grid_.selection, ground);
    ref_coarse_.build(none, origin, coarse_.grid, coarse_.selection, ground);
    cur_coarse_.build(none, origin, coarse_.grid, coarse_.selection, ground);
  }
}

std::vector<int> LoopCloser::candidates(const SlamMap& map, int newest,
                                        const std::vector<double>& path_length) const {
  const LoopParams& l = params_.loop;
  const Eigen::Vector3d p = map.keyframes[newest].pose.translation();
  std::vector<std::pair<double, int>> near;
  for (int j = 0; j < newest; ++j) {
    if (path_length[newest] - path_length[j] < l.min_path) continue;
    const double d = (map.keyframes[j].pose.translation() - p).head<2>().norm();
    if (d <= l.search_radius) near.emplace_back(d, j);
  }
  std::sort(near.begin(), near.end());
  std::vector<int> out;
  for (const auto& [d, j] : near) out.push_back(j);
  return out;
}

LoopCandidate LoopCloser::verify(const SlamMap& map, int from_id, int to_id,
                                 const Eigen::Isometry3d& guess, PoseEdge& edge,
                                 LoopSearch search) const {
  LoopCandidate c;
  c.from = from_id;
  c.to = to_id;
  c.tracked = search == LoopSearch::kFromGuess;
  WeightedCloud from_buffer, to_buffer;
  const WeightedCloud& from_cloud = submapCloud(map, from_id, from_buffer);
  const WeightedCloud& to_cloud = submapCloud(map, to_id, to_buffer);
  if (from_cloud.empty() || to_cloud.empty()) {
    c.reason = "empty keyframe cloud";
    return c;
  }
  // The coarse search first: most candidates of a drive end there, and then the verification
  // grids (several levels and their gradient fields, the larger part of a rejection's cost
  // before) are not built at all.
  std::vector<Eigen::Isometry3d> starts;
  if (c.tracked) {
    starts.push_back(guess);
  } else {
    starts = searchBasins(from_cloud, to_cloud, guess);
    if (starts.empty()) {
      c.reason = "no start of the coarse search overlaps";
      return c;
    }
  }
  const bool ground = grid_.includeGround();
  ref_.build(from_cloud, Eigen::Isometry3d::Identity(), grid_.grid, grid_.selection, ground);
  cur_.build(to_cloud, Eigen::Isometry3d::Identity(), grid_.grid, grid_.selection, ground);
  if (ref_.empty() || cur_.empty()) {
    c.reason = "empty keyframe cloud";
    return c;
  }
  const DirectAligner aligner(grid_.solver);
  const double selected = static_cast<double>(cur_.levels().front().cells.size());
  std::vector<AlignmentResult> refined;
  for (const Eigen::Isometry3d& start : starts) refined.push_back(aligner.align(ref_, cur_, start));
  if (params_.odometry.levelling == 1 && grid_.solver.dof == 3) {
    // z, roll and pitch of the loop from the ground, as the odometry measures them: the guess
    // carries the drift of the whole way round (0.6 deg and 0.16 m on the simulated block).
    const size_t k = groundLevel(cur_);
    GroundSurface ground;
    fitGroundSurface(cur_.levels()[k].grid, GroundSurfaceParams(), ground);
    // x, y and yaw were registered at the guess's height and tilt: registered again at the
    // ground's, then levelled again.
    const auto level = [&](Eigen::Isometry3d& pose) {
      const GroundAlignment g =
          alignToGround(ref_.levels()[k].grid, ground.cells, pose, grid_.solver.rotation_scale);
      if (g.aligned) pose = g.pose;
      return g.aligned;
    };
    for (AlignmentResult& r : refined) {
      if (!ground.found) break;
      Eigen::Isometry3d pose = r.pose;
      if (!level(pose)) continue;
      r = aligner.align(ref_, cur_, pose);
      level(r.pose);
    }
  }
  judge(refined, selected, guess, c, edge);
  return c;
}

std::pair<int, int> LoopCloser::submapWindow(int count, int id) const {
  const int n = params_.loop.submap_keyframes;
  if (n <= 1) return {id, id};
  const int first = std::clamp(id - (n - 1) / 2, 0, std::max(0, count - n));
  return {first, std::min(count - 1, first + n - 1)};
}

const WeightedCloud& LoopCloser::submapCloud(const SlamMap& map, int id,
                                             WeightedCloud& buffer) const {
  if (params_.loop.submap_keyframes <= 1) {
    return map.keyframeCloud(static_cast<size_t>(id), buffer);
  }
  const auto [first, last] = submapWindow(static_cast<int>(map.keyframes.size()), id);
  buffer.clear();
  const Eigen::Isometry3d to_id = map.keyframes[static_cast<size_t>(id)].pose.inverse();
  WeightedCloud read;
  for (int j = first; j <= last; ++j) {
    const WeightedCloud& cloud = map.keyframeCloud(static_cast<size_t>(j), read);
    const Eigen::Isometry3f T = (to_id * map.keyframes[static_cast<size_t>(j)].pose).cast<float>();
    buffer.reserve(buffer.size() + cloud.size());
    for (const WeightedPoint& w : cloud) buffer.push_back(WeightedPoint{T * w.p, w.n});
  }
  return buffer;
}

std::vector<Eigen::Isometry3d> LoopCloser::searchBasins(const WeightedCloud& from_cloud,
                                                        const WeightedCloud& to_cloud,
                                                        const Eigen::Isometry3d& guess) const {
  const bool ground = grid_.includeGround();
  // Drift puts the guess metres and degrees off, beyond the basin of one registration: search
  // a lattice of starts on a coarse grid first, and keep the best-fitting basin.
  ref_coarse_.build(from_cloud, Eigen::Isometry3d::Identity(), coarse_.grid, coarse_.selection,
                    ground);
  cur_coarse_.build(to_cloud, Eigen::Isometry3d::Identity(), coarse_.grid, coarse_.selection,
                    ground);
  const DirectAligner coarse_aligner(coarse_.solver);
  struct Basin {
    Eigen::Isometry3d pose;
    double rms;
  };
  std::vector<Basin> basins;  // distinct coarse results, each with its best fit
  for (const double dx : kSearchOffsets) {
    for (const double dy : kSearchOffsets) {
      for (const double dyaw : kSearchYaws) {
        const Eigen::Isometry3d start = poseFromXYZYPR(dx, dy, 0.0, dyaw * kDeg, 0.0, 0.0) * guess;
        const AlignmentResult r = coarse_aligner.align(ref_coarse_, cur_coarse_, start);
        if (r.cells < grid_.solver.min_cells) continue;
        auto same = std::find_if(basins.begin(), basins.end(), [&](const Basin& b) {
          const Eigen::Isometry3d d = b.pose.inverse() * r.pose;
          return d.translation().norm() < kDistinctBasin &&
                 Eigen::AngleAxisd(d.linear()).angle() < kDistinctBasinAngle;
        });
        if (same == basins.end()) {
          basins.push_back(Basin{r.pose, r.rms_height_error});
        } else if (r.rms_height_error < same->rms) {
          *same = Basin{r.pose, r.rms_height_error};
        }
      }
    }
  }
  // The most promising basins, to be refined at full resolution.
  std::sort(basins.begin(), basins.end(),
            [](const Basin& a, const Basin& b) { return a.rms < b.rms; });
  std::vector<Eigen::Isometry3d> starts;
  for (size_t i = 0; i < basins.size() && i < kRefinedBasins; ++i) starts.push_back(basins[i].pose);
  return starts;
}

void LoopCloser::judge(const std::vector<AlignmentResult>& refined, double selected,
                       const Eigen::Isometry3d& guess, LoopCandidate& c, PoseEdge& edge) const {
  const LoopParams& l = params_.loop;
  // Keep the best fit.
  const auto fit = [&](const AlignmentResult& r) {
    const double inliers = selected > 0 ? r.cells / selected : 0.0;
    return inliers >= l.min_inliers ? r.rms_height_error : std::numeric_limits<double>::infinity();
  };
  const auto best = std::min_element(
      refined.begin(), refined.end(),
      [&](const AlignmentResult& a, const AlignmentResult& b) { return fit(a) < fit(b); });
  // A true loop has one basin: another pose fitting nearly as well means a repetitive or
  // ambiguous place (parallel streets, a row of identical buildings), so it is refused.
  for (const AlignmentResult& other : refined) {
    const Eigen::Isometry3d d = best->pose.inverse() * other.pose;
    const bool elsewhere = d.translation().norm() > kDistinctBasin ||
                           Eigen::AngleAxisd(d.linear()).angle() > kDistinctBasinAngle;
    if (elsewhere && fit(other) < fit(*best) * kAmbiguityRatio) {
      c.reason = describe("ambiguous: a pose this far (m) fits nearly as well",
                          d.translation().norm(), kDistinctBasin);
      return;
    }
  }
  const AlignmentResult r = *best;
  c.rms_height_error = r.rms_height_error;
  c.correction = (guess.inverse() * r.pose).translation().norm();
  const double inliers = selected > 0 ? r.cells / selected : 0.0;
  if (r.degenerate) {
    c.reason = "degenerate registration";
  } else if (r.rms_height_error > l.max_rms) {
    c.reason = describe("rms height error", r.rms_height_error, l.max_rms);
  } else if (inliers < l.min_inliers) {
    c.reason = describe("inlier fraction", inliers, l.min_inliers);
  } else if (c.correction > l.max_correction) {
    c.reason = describe("correction (m)", c.correction, l.max_correction);
  } else if (!c.tracked &&
             Eigen::AngleAxisd((guess.inverse() * r.pose).linear()).angle() > kMaxLatticeRotation) {
    c.reason = describe("rotation from the guess (deg)",
                        Eigen::AngleAxisd((guess.inverse() * r.pose).linear()).angle() / kDeg,
                        kMaxLatticeRotation / kDeg);
  } else if (c.tracked && c.correction > kDistinctBasin) {
    // The guess should have been good: a registration that moved this far may have slipped
    // into another basin, which only the lattice search can tell.
    c.reason = describe("correction from a tracked guess (m)", c.correction, kDistinctBasin);
  } else if (c.tracked &&
             Eigen::AngleAxisd((guess.inverse() * r.pose).linear()).angle() > kDistinctBasinAngle) {
    c.reason = describe("rotation from a tracked guess (deg)",
                        Eigen::AngleAxisd((guess.inverse() * r.pose).linear()).angle() / kDeg,
                        kDistinctBasinAngle / kDeg);
  } else {
    c.accepted = true;
    c.reason = "accepted";
  }
  if (c.accepted) {
    edge.from = c.from;
    edge.to = c.to;
    edge.relative = r.pose;
    edge.information =
        edgeInformation(r.pose, r.covariance, l.min_sigma_xy, l.min_sigma_angle * kDeg);
    edge.loop = true;
  }
}

}  // namespace dlo
