// LocalHeightMap: windows equal a direct rasterisation of the live scans, exact eviction by age
// and distance, no aliasing on the torus, bad points skipped.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "dlo/core/height_grid.h"
#include "dlo/core/local_height_map.h"
#include "dlo/core/rigid_transform.h"

namespace dlo {
namespace {

constexpr double kRes = 0.5;
constexpr int kCells = 40;  // a 20 m window

PointCloud randomScan(std::mt19937& rng, int n) {
  std::uniform_real_distribution<float> xy(-12.0f, 12.0f);
  std::uniform_real_distribution<float> z(-1.0f, 3.0f);
  PointCloud pts;
  for (int i = 0; i < n; ++i) pts.emplace_back(xy(rng), xy(rng), z(rng));
  return pts;
}

/// The window of `map` around `position` as a grid.
HeightGrid window(const LocalHeightMap& map, const Eigen::Vector3d& position,
                  Eigen::Isometry3d& pose) {
  pose = map.windowPose(position);
  HeightGrid g;
  g.accumulateCells(GridGeometry::centred(kCells, kCells, kRes), 1,
                    [&](std::uint32_t* count, float* sum) { map.fillWindow(pose, count, sum); });
  return g;
}

/// What the window should hold: the scans rasterised directly in the window's frame, each
/// cropped to its own window as insert() does.
HeightGrid direct(const std::vector<PointCloud>& scans, const std::vector<Eigen::Isometry3d>& poses,
                  const Eigen::Isometry3d& window_pose) {
  PointCloud all;
  const float half = static_cast<float>(0.5 * kCells * kRes);
  for (size_t s = 0; s < scans.size(); ++s) {
    const Eigen::Isometry3f T = (window_pose.inverse() * poses[s]).cast<float>();
    for (const Eigen::Vector3f& p : scans[s]) {
      if (std::fabs(p.x()) <= half && std::fabs(p.y()) <= half) all.push_back(T * p);
    }
  }
  return HeightGrid::fromPoints(all, GridGeometry::centred(kCells, kCells, kRes), 1, -100.0, 100.0);
}

void expectSameCells(const HeightGrid& a, const HeightGrid& b) {
  int differing = 0;
  for (int r = 0; r < a.rows(); ++r) {
    for (int c = 0; c < a.cols(); ++c) {
      // A point on a cell boundary may fall either side after the two different roundings.
      if (a.count(r, c) != b.count(r, c)) ++differing;
      if (a.isValid(r, c) && b.isValid(r, c) && a.count(r, c) == b.count(r, c)) {
        EXPECT_NEAR(a.height(r, c), b.height(r, c), 1e-4) << "cell " << r << ", " << c;
      }
    }
  }
  EXPECT_LE(differing, 2);
}

TEST(LocalHeightMap, WindowsEqualTheLiveScansRasterisedDirectlyAlongADrive) {
  std::mt19937 rng(11);
  LocalHeightMap map(kRes, kCells, kCells, 5);
  std::vector<PointCloud> scans;
  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 40; ++k) {
    // A curving drive of 1.3 m per scan, heading changing, some height and tilt.
    const Eigen::Isometry3d pose =
        poseFromXYZYPR(1.3 * k, 4.0 * std::sin(0.1 * k), 0.05 * k, 0.07 * k, 0.01, -0.02);
    scans.push_back(randomScan(rng, 3000));
    poses.push_back(pose);
    map.insert(scans.back(), pose, -100.0, 100.0);
    ASSERT_EQ(map.scans(), std::min<size_t>(k + 1, 5));
    const size_t live = map.scans();
    Eigen::Isometry3d wpose;
    const HeightGrid got = window(map, pose.translation(), wpose);
    const HeightGrid want =
        direct(std::vector<PointCloud>(scans.end() - live, scans.end()),
               std::vector<Eigen::Isometry3d>(poses.end() - live, poses.end()), wpose);
    SCOPED_TRACE("scan " + std::to_string(k));
    expectSameCells(got, want);
  }
}

TEST(LocalHeightMap, EvictedScansLeaveExactZeros) {
  std::mt19937 rng(3);
  LocalHeightMap map(kRes, kCells, kCells, 2);
  const Eigen::Isometry3d far = poseFromXYZYPR(100.0, 0, 0, 0, 0, 0);
  map.insert(randomScan(rng, 2000), Eigen::Isometry3d::Identity(), -100.0, 100.0);
  map.insert(randomScan(rng, 2000), far, -100.0, 100.0);
  // 100 m is beyond the eviction distance: the first scan went at once.
  EXPECT_GT(100.0, map.evictionDistance());
  EXPECT_EQ(map.scans(), 1u);
  Eigen::Isometry3d wpose;
  const HeightGrid g = window(map, Eigen::Vector3d::Zero(), wpose);
  EXPECT_EQ(g.validCellCount(), 0);
  map.clear();
  EXPECT_EQ(map.scans(), 0u);
  EXPECT_EQ(window(map, far.translation(), wpose).validCellCount(), 0);
}

TEST(LocalHeightMap, SkipsNonFinitePointsAndPointsOutsideTheWindowOrHeights) {
  LocalHeightMap map(kRes, kCells, kCells, 3);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  PointCloud pts = {{nan, 0, 0},        {0, nan, 0},  {0, 0, nan},
                    {inf, 0, 0},        {0, 0, -inf}, {10.2f, 0, 0},  // outside the 20 m window
                    {1.2f, 1.2f, 5.0f},                               // above max_z
                    {1.2f, 1.2f, 0.5f}};
  map.insert(pts, Eigen::Isometry3d::Identity(), -2.0, 2.0);
  Eigen::Isometry3d wpose;
  const HeightGrid g = window(map, Eigen::Vector3d::Zero(), wpose);
  EXPECT_EQ(g.validCellCount(), 1);
  const GridGeometry& geo = g.geometry();
  const int c = static_cast<int>(geo.u(1.2 - wpose.translation().x()));
  const int r = static_cast<int>(geo.v(1.2 - wpose.translation().y()));
  EXPECT_EQ(g.count(r, c), 1u);
  EXPECT_FLOAT_EQ(g.height(r, c), 0.5f);
}

TEST(LocalHeightMap, WindowCellsAreTheMapCells) {
  // Odd and even windows: the window's left edge always falls on a map cell boundary.
  for (const int cells : {40, 41}) {
    LocalHeightMap map(kRes, cells, cells, 1);
    const Eigen::Isometry3d w = map.windowPose(Eigen::Vector3d(3.37, -8.91, 1.0));
    const double left = w.translation().x() - 0.5 * cells * kRes;
    const double bottom = w.translation().y() - 0.5 * cells * kRes;
    EXPECT_NEAR(left / kRes, std::round(left / kRes), 1e-9);
    EXPECT_NEAR(bottom / kRes, std::round(bottom / kRes), 1e-9);
    EXPECT_NEAR(w.translation().x(), 3.37, kRes);
    EXPECT_NEAR(w.translation().y(), -8.91, kRes);
    EXPECT_EQ(w.translation().z(), 0.0);
  }
}

TEST(LocalHeightMap, RejectsImpossibleSizes) {
  EXPECT_THROW(LocalHeightMap(0.0, 10, 10, 1), std::invalid_argument);
  EXPECT_THROW(LocalHeightMap(0.1, 0, 10, 1), std::invalid_argument);
  EXPECT_THROW(LocalHeightMap(0.1, 10, 10, 0), std::invalid_argument);
}

}  // namespace
}  // namespace dlo
