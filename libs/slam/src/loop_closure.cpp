#include "dlo/slam/loop_closure.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "dlo/slam/keyframe_graph.h"

namespace dlo {

namespace {
constexpr double kDeg = M_PI / 180.0;

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

LoopCandidate LoopCloser::verify(const Keyframe& from, const Keyframe& to,
                                 const Eigen::Isometry3d& guess, PoseEdge& edge) const {
  const LoopParams& l = params_.loop;
  LoopCandidate c;
  c.from = from.id;
  c.to = to.id;
  const bool ground = grid_.includeGround();
  HeightFrame ref, cur;
  ref.build(from.cloud, Eigen::Isometry3d::Identity(), grid_.grid, grid_.selection, ground);
  cur.build(to.cloud, Eigen::Isometry3d::Identity(), grid_.grid, grid_.selection, ground);
  if (ref.empty() || cur.empty()) {
    c.reason = "empty keyframe cloud";
    return c;
  }
  const DirectAligner aligner(grid_.solver);
  const AlignmentResult r = aligner.align(ref, cur, guess);
  c.rms_height_error = r.rms_height_error;
  c.correction = (guess.inverse() * r.pose).translation().norm();
  const double selected = static_cast<double>(cur.levels().front().cells.size());
  const double inliers = selected > 0 ? r.cells / selected : 0.0;
  if (r.degenerate) {
    c.reason = "degenerate registration";
  } else if (r.rms_height_error > l.max_rms) {
    c.reason = describe("rms height error", r.rms_height_error, l.max_rms);
  } else if (inliers < l.min_inliers) {
    c.reason = describe("inlier fraction", inliers, l.min_inliers);
  } else if (c.correction > l.max_correction) {
    c.reason = describe("correction (m)", c.correction, l.max_correction);
  } else {
    // A true loop has one basin: started elsewhere, the registration must land on the same pose.
    const Eigen::Isometry3d shifted = guess * poseFromXYZYPR(0.5, -0.3, 0.0, 2.0 * kDeg, 0.0, 0.0);
    const AlignmentResult again = aligner.align(ref, cur, shifted);
    const double disagreement = (r.pose.inverse() * again.pose).translation().norm();
    if (disagreement > l.max_disagreement) {
      c.reason = describe("disagreement between two starts (m)", disagreement, l.max_disagreement);
    } else {
      c.accepted = true;
      c.reason = "accepted";
    }
  }
  if (c.accepted) {
    edge.from = from.id;
    edge.to = to.id;
    edge.relative = r.pose;
    edge.information =
        edgeInformation(r.pose, r.covariance, l.min_sigma_xy, l.min_sigma_angle * kDeg);
    edge.loop = true;
  }
  return c;
}

}  // namespace dlo
