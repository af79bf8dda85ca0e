#include "synthetic_map.h"

#include <cmath>

namespace dlo::test {

namespace {

using W = SyntheticWorld;

/// Points of the world (ground on a world-aligned 0.4 m lattice, box faces every 0.1 m) within
/// `range` of `centre`.
PointCloud worldPointsAround(const Eigen::Vector3d& centre, double range) {
  PointCloud pts;
  auto keep = [&](double x, double y, double z) {
    if (std::hypot(x - centre.x(), y - centre.y()) <= range) {
      pts.emplace_back(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
    }
  };
  auto inBox = [](double x, double y) {
    return std::abs(x - W::kBoxX) <= W::kBoxHalfSide && std::abs(y - W::kBoxY) <= W::kBoxHalfSide;
  };
  const double g = 0.4;
  for (double x = std::floor((centre.x() - range) / g) * g; x <= centre.x() + range; x += g) {
    for (double y = std::floor((centre.y() - range) / g) * g; y <= centre.y() + range; y += g) {
      if (!inBox(x, y)) keep(x, y, 0.0);
    }
  }
  const double s = W::kBoxHalfSide;
  for (double u = -s; u <= s + 1e-9; u += 0.1) {
    for (double v = -s; v <= s + 1e-9; v += 0.1) keep(W::kBoxX + u, W::kBoxY + v, W::kBoxHeight);
    for (double z = 0.0; z < W::kBoxHeight; z += 0.1) {
      keep(W::kBoxX + u, W::kBoxY - s, z);
      keep(W::kBoxX + u, W::kBoxY + s, z);
      keep(W::kBoxX - s, W::kBoxY + u, z);
      keep(W::kBoxX + s, W::kBoxY + u, z);
    }
  }
  return pts;
}

Eigen::Isometry3d circlePose(double angle) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() =
      Eigen::Vector3d(W::kRadius * std::sin(angle), W::kRadius - W::kRadius * std::cos(angle), 0);
  p.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

}  // namespace

SlamMap makeSyntheticMap() {
  SlamMap map;
  const double step = 2.0 * M_PI / W::kKeyframes;
  for (int k = 0; k < W::kKeyframes; ++k) {
    Keyframe kf;
    kf.id = k;
    kf.frame = k * W::kFramesPerKeyframe;
    kf.time = 100.0 + 0.1 * kf.frame;
    kf.pose = circlePose(k * step);
    PointCloud local;
    for (const Eigen::Vector3f& p : worldPointsAround(kf.pose.translation(), 20.0)) {
      local.push_back((kf.pose.inverse() * p.cast<double>()).cast<float>());
    }
    kf.cloud = voxelise(local, 0.2);
    map.keyframes.push_back(std::move(kf));
    for (int f = 0; f < W::kFramesPerKeyframe; ++f) {
      FramePose frame;
      frame.keyframe = k;
      frame.time = 100.0 + 0.1 * (k * W::kFramesPerKeyframe + f);
      frame.relative = circlePose(k * step).inverse() *
                       circlePose((k + static_cast<double>(f) / W::kFramesPerKeyframe) * step);
      map.frames.push_back(frame);
    }
  }
  auto edge = [&](int from, int to, bool loop) {
    PoseEdge e;
    e.from = from;
    e.to = to;
    e.relative = map.keyframes[from].pose.inverse() * map.keyframes[to].pose;
    e.information = Matrix6d::Identity();
    e.information.diagonal() << 100, 200, 300, 400, 500, 600;
    e.loop = loop;
    map.edges.push_back(e);
  };
  for (int k = 0; k + 1 < W::kKeyframes; ++k) edge(k, k + 1, false);
  edge(W::kKeyframes - 1, 0, true);
  LoopCandidate c;
  c.from = 0;
  c.to = W::kKeyframes - 1;
  c.accepted = true;
  c.reason = "accepted";
  map.loop_candidates.push_back(c);
  return map;
}

}  // namespace dlo::test
