#include "dlo/slam/reference_model.h"

#include <utility>
#include <vector>

namespace dlo {

std::unique_ptr<ReferenceModel> ReferenceModel::make(const SlamParams& params) {
  switch (params.odometry.reference) {
    case Reference::kPreviousScan:
      return std::make_unique<PreviousScanReference>(params);
    case Reference::kKeyframe:
      return std::make_unique<KeyframeMapReference>(params, 1);
    case Reference::kKeyframeMap:
      return std::make_unique<KeyframeMapReference>(
          params, static_cast<size_t>(params.odometry.local_map_keyframes));
    case Reference::kScanMap:
      return std::make_unique<ScanMapReference>(params);
  }
  throw std::invalid_argument("ReferenceModel::make: odometry.reference out of range");
}

void ReferenceModel::addKeyframe(const Eigen::Isometry3d&, WeightedCloud) {}

void ReferenceModel::afterScan(HeightFrame&, const PointCloud&, const Eigen::Isometry3d&, bool) {}

void ReferenceModel::redoFirstScan(const PointCloud&, const Eigen::Isometry3d&, WeightedCloud) {}

void PreviousScanReference::afterScan(HeightFrame& current, const PointCloud&,
                                      const Eigen::Isometry3d& pose, bool) {
  // Frame to frame, as in the paper: this scan is the next reference, measured or not.
  if (current.empty()) return;
  std::swap(frame_, current);
  pose_ = pose;
  ready_ = true;
}

void KeyframeMapReference::addKeyframe(const Eigen::Isometry3d& pose, WeightedCloud fine) {
  // A keyframe taken where the newest one was (a turn on the spot makes one every
  // keyframe_angle) carries the same pattern of rings again, which pulls registrations towards
  // where both were taken: it replaces that one instead of joining it (local_map_spacing).
  const double spacing = params_.odometry.local_map_spacing;
  if (keyframes_ > 1 && spacing > 0.0 && !recent_.empty() &&
      (recent_.back().pose.translation() - pose.translation()).head<2>().norm() < spacing) {
    recent_.pop_back();
  }
  recent_.push_back(Keyframe{pose, std::move(fine)});
  while (recent_.size() > keyframes_) recent_.pop_front();
  const double extent = params_.odometry.local_map_extent;
  while (extent > 0.0 && recent_.size() > 1 &&
         (recent_.front().pose.translation() - pose.translation()).norm() > extent) {
    recent_.pop_front();
  }
  rebuild();
}

void KeyframeMapReference::redoFirstScan(const PointCloud&, const Eigen::Isometry3d& pose,
                                         WeightedCloud fine) {
  // Only the first scan's own keyframe is redone: one that replaced it (local_map_spacing) or
  // came after it keeps its cloud.
  if (recent_.empty() || recent_.front().pose.matrix() != pose.matrix()) return;
  recent_.front().cloud = std::move(fine);
  rebuild();
}

void KeyframeMapReference::rebuild() {
  // All recent keyframes, expressed in the newest one's frame, in one grid: the mean height of
  // a cell then averages every keyframe that saw it.
  const DloParams& reg = params_.registration;
  const Eigen::Isometry3d& anchor = recent_.back().pose;
  std::vector<PosedCloud> parts;
  for (const Keyframe& k : recent_)
    parts.push_back(PosedCloud{&k.cloud, anchor.inverse() * k.pose});
  frame_.build(parts, reg.grid, reg.selection, reg.includeGround(), FrameUse::kReferenceOnly);
  pose_ = anchor;
  ready_ = true;
}

LocalHeightMap& ScanMapReference::map() {
  if (!map_) {
    const HeightGridParams& g = params_.registration.grid;
    map_.emplace(g.resolution, g.cols, g.rows, params_.odometry.local_map_scans);
  }
  return *map_;
}

void ScanMapReference::afterScan(HeightFrame& current, const PointCloud& points,
                                 const Eigen::Isometry3d& pose, bool measured) {
  // Only scans whose pose was measured go into the map: a rejected one (a large moving object,
  // a wrong basin) would smear what the next scans are registered against.
  if (current.empty() || !measured) return;
  const DloParams& reg = params_.registration;
  LocalHeightMap& m = map();
  // Scans taken close together add the same sensor-locked pattern again (see
  // OdometryParams::local_map_spacing): such a scan only moves the window.
  const Eigen::Vector2d here = pose.translation().head<2>();
  if (m.scans() == 0 || (here - last_position_).norm() >= params_.odometry.local_map_spacing) {
    m.insert(points, pose, reg.grid.min_z, reg.grid.max_z);
    last_position_ = here;
  }
  // The reference grid is axis-aligned in the odometry frame, its cells the map's own: no
  // resampling, the registration takes the heading into its initial guess.
  pose_ = m.windowPose(pose.translation());
  frame_.build([&](std::uint32_t* count, float* sum) { m.fillWindow(pose_, count, sum); }, reg.grid,
               reg.selection, reg.includeGround(), FrameUse::kReferenceOnly);
  ready_ = true;
}

void ScanMapReference::redoFirstScan(const PointCloud& points, const Eigen::Isometry3d& pose,
                                     WeightedCloud) {
  // The map starts again from the deskewed first scan (at 10 m/s the raw one is stretched by a
  // metre); the scan that follows joins it next.
  LocalHeightMap& m = map();
  m.clear();
  const DloParams& reg = params_.registration;
  m.insert(points, pose, reg.grid.min_z, reg.grid.max_z);
  last_position_ = pose.translation().head<2>();
}

}  // namespace dlo
