// The keyframe map that scans are registered against (odometry.reference = keyframe_map): which
// keyframes it fuses.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>

#include "dlo/slam/reference_model.h"

namespace dlo {
namespace {

/// Ten points on one spot (vehicle frame): a cell of the map with them holds ten points.
WeightedCloud blobAt(float x, float y) {
  return WeightedCloud{WeightedPoint{Eigen::Vector3f(x, y, 1.0f), 10u}};
}

/// Points in the finest cell of the reference under (x, y) of the newest keyframe's frame.
std::uint32_t pointsAt(const ReferenceModel& reference, double x, double y) {
  const HeightGrid& grid = reference.frame().levels().front().grid;
  const int col = static_cast<int>(std::floor(grid.geometry().u(x)));
  const int row = static_cast<int>(std::floor(grid.geometry().v(y)));
  return grid.count(row, col);
}

Eigen::Isometry3d poseAt(double x, double yaw_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation().x() = x;
  pose.linear() = Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).matrix();
  return pose;
}

/// A keyframe at (0, 0) that sees a spot 5 m ahead of it, then a keyframe at `second` that sees
/// another spot 5 m behind it: the points the map holds at each spot.
struct TwoSpots {
  std::uint32_t first_spot;
  std::uint32_t second_spot;
};

TwoSpots mapOfTwoKeyframes(double spacing, const Eigen::Isometry3d& second) {
  SlamParams params;
  params.odometry.reference = Reference::kKeyframeMap;
  params.odometry.local_map_spacing = spacing;
  const auto reference = ReferenceModel::make(params);
  reference->addKeyframe(Eigen::Isometry3d::Identity(), blobAt(5.0f, 0.0f));
  reference->addKeyframe(second, blobAt(-5.0f, 0.0f));
  const Eigen::Vector3d first_spot = second.inverse() * Eigen::Vector3d(5.0, 0.0, 1.0);
  return {pointsAt(*reference, first_spot.x(), first_spot.y()), pointsAt(*reference, -5.0, 0.0)};
}

TEST(KeyframeMap, AKeyframeTakenWhereTheNewestStoodReplacesIt) {
  // Turning on the spot: 10 deg round, 0.3 m on (a sensor ahead of the axis). The same pattern
  // of rings twice would pull the next scans towards this place, so only the newer stays.
  const TwoSpots turned = mapOfTwoKeyframes(0.6, poseAt(0.3, 10.0));
  EXPECT_EQ(turned.first_spot, 0u);
  EXPECT_EQ(turned.second_spot, 10u);
}

TEST(KeyframeMap, KeyframesSpreadAlongTheDriveAreFused) {
  const TwoSpots driven = mapOfTwoKeyframes(0.6, poseAt(2.0, 0.0));
  EXPECT_EQ(driven.first_spot, 10u);
  EXPECT_EQ(driven.second_spot, 10u);
  // With no spacing every keyframe joins, wherever it was taken.
  const TwoSpots unspaced = mapOfTwoKeyframes(0.0, poseAt(0.3, 10.0));
  EXPECT_EQ(unspaced.first_spot, 10u);
  EXPECT_EQ(unspaced.second_spot, 10u);
}

TEST(KeyframeMap, TheFirstScanRedoneDoesNotOverwriteTheKeyframeThatReplacedIt) {
  SlamParams params;
  params.odometry.reference = Reference::kKeyframeMap;
  const auto reference = ReferenceModel::make(params);
  reference->addKeyframe(Eigen::Isometry3d::Identity(), blobAt(5.0f, 0.0f));
  reference->addKeyframe(poseAt(0.2, 10.0), blobAt(-5.0f, 0.0f));
  // The first scan deskewed afterwards (LidarOdometry::redoFirstKeyframe) belongs to the
  // keyframe that is no longer in the map.
  reference->redoFirstScan(PointCloud(), Eigen::Isometry3d::Identity(), blobAt(3.0f, 3.0f));
  EXPECT_EQ(pointsAt(*reference, -5.0, 0.0), 10u);
  const Eigen::Vector3d redone = poseAt(0.2, 10.0).inverse() * Eigen::Vector3d(3.0, 3.0, 1.0);
  EXPECT_EQ(pointsAt(*reference, redone.x(), redone.y()), 0u);
}

TEST(KeyframeMap, TheFirstScanRedoneReplacesItsOwnKeyframesCloud) {
  SlamParams params;
  params.odometry.reference = Reference::kKeyframeMap;
  const auto reference = ReferenceModel::make(params);
  reference->addKeyframe(Eigen::Isometry3d::Identity(), blobAt(5.0f, 0.0f));
  reference->redoFirstScan(PointCloud(), Eigen::Isometry3d::Identity(), blobAt(3.0f, 3.0f));
  EXPECT_EQ(pointsAt(*reference, 5.0, 0.0), 0u);
  EXPECT_EQ(pointsAt(*reference, 3.0, 3.0), 10u);
}

}  // namespace
}  // namespace dlo
