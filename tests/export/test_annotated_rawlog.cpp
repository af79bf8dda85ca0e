// The annotated rawlog: its emulated 2D scan on a synthetic scene, and what MRPT reads back.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "../temp_dir.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/export/annotated_rawlog.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

constexpr float kGround = -1.8f;  ///< the ground below a roof-mounted sensor

/// A scan in the vehicle frame: flat ground within 25 m, a wall across x = 10 (y in [-4, 4],
/// 3 m high, sampled every 2 cm: denser than the rays), a pole at (-8, 3), a 0.13 m kerb beyond y =
/// 6 (a sidewalk), and a canopy 4.5 m above the ground around (0, -8) with nothing under it.
PointCloud syntheticScene() {
  PointCloud points;
  for (float x = -25.0f; x <= 25.0f; x += 0.25f) {
    for (float y = -25.0f; y <= 25.0f; y += 0.25f) {
      if (x * x + y * y > 25.0f * 25.0f) continue;
      points.emplace_back(x, y, y > 6.0f ? kGround + 0.13f : kGround);
    }
  }
  for (float y = -4.0f; y <= 4.0f; y += 0.02f)
    for (float z = kGround; z <= kGround + 3.0f; z += 0.1f) points.emplace_back(10.0f, y, z);
  for (float z = kGround; z <= kGround + 3.0f; z += 0.05f) points.emplace_back(-8.0f, 3.0f, z);
  for (float x = -2.0f; x <= 2.0f; x += 0.2f)
    for (float y = -10.0f; y <= -6.0f; y += 0.2f) points.emplace_back(x, y, kGround + 4.5f);
  return points;
}

/// The ray of `scan` that points at `angle` (radians from the vehicle's x axis).
size_t rayAt(const mrpt::obs::CObservation2DRangeScan& scan, double angle) {
  const size_t n = scan.getScanSize();
  size_t best = 0;
  for (size_t i = 0; i < n; ++i) {
    const double d = std::abs(std::remainder(scan.getScanAngle(i) - angle, 2.0 * M_PI));
    if (d < std::abs(std::remainder(scan.getScanAngle(best) - angle, 2.0 * M_PI))) best = i;
  }
  return best;
}

TEST(Emulated2DScan, SeesWallsAndPolesNotKerbsOrCanopies) {
  const auto scan = emulate2DScan(syntheticScene(), mrpt::Clock::fromDouble(100.0));
  ASSERT_EQ(scan->getScanSize(), 720u);
  EXPECT_TRUE(scan->rightToLeft);
  EXPECT_FLOAT_EQ(scan->maxRange, 60.0f);
  EXPECT_EQ(scan->sensorLabel, "DLO_2D_SCAN");
  EXPECT_DOUBLE_EQ(mrpt::Clock::toDouble(scan->timestamp), 100.0);
  // Half a degree apart, none twice: -179.75 ... 179.75 degrees.
  EXPECT_NEAR(scan->getScanAngle(0), -M_PI + M_PI / 720.0, 1e-5);
  EXPECT_NEAR(scan->getScanAngle(719), M_PI - M_PI / 720.0, 1e-5);

  const size_t wall = rayAt(*scan, 0.0);
  ASSERT_TRUE(scan->getScanRangeValidity(wall));
  EXPECT_NEAR(scan->getScanRange(wall), 10.0, 0.01);
  // The wall's edge, 4 m to the side: still the wall, farther along the ray.
  const size_t edge = rayAt(*scan, std::atan2(3.9, 10.0));
  ASSERT_TRUE(scan->getScanRangeValidity(edge));
  EXPECT_NEAR(scan->getScanRange(edge), std::hypot(10.0, 3.9), 0.1);
  const size_t pole = rayAt(*scan, std::atan2(3.0, -8.0));
  ASSERT_TRUE(scan->getScanRangeValidity(pole));
  EXPECT_NEAR(scan->getScanRange(pole), std::hypot(8.0, 3.0), 0.01);
  // The kerb (ahead on the left), the canopy (right) and open ground (behind): no return.
  for (const double angle : {M_PI / 2.0, -M_PI / 2.0, M_PI - 0.3}) {
    EXPECT_FALSE(scan->getScanRangeValidity(rayAt(*scan, angle))) << angle;
  }
  size_t valid = 0;
  for (size_t i = 0; i < scan->getScanSize(); ++i) valid += scan->getScanRangeValidity(i);
  // The wall spans 2 x 21.8 degrees (87 rays), the pole one or two.
  EXPECT_GE(valid, 85u);
  EXPECT_LE(valid, 92u);
}

TEST(Emulated2DScan, ObstaclesBeyondItsRangeAreNotSeen) {
  Emulated2DScanOptions options;
  options.max_range = 9.0;
  const auto scan = emulate2DScan(syntheticScene(), mrpt::Clock::fromDouble(0.0), options);
  EXPECT_FALSE(scan->getScanRangeValidity(rayAt(*scan, 0.0)));  // the wall, 10 m away
  EXPECT_TRUE(scan->getScanRangeValidity(rayAt(*scan, std::atan2(3.0, -8.0))));  // 8.5 m
  options.rays = 1;
  EXPECT_THROW(emulate2DScan({}, mrpt::Clock::fromDouble(0.0), options), std::invalid_argument);
}

TEST(Emulated2DScan, AnEmptyScanGivesRaysWithNoReturn) {
  const auto scan = emulate2DScan({}, mrpt::Clock::fromDouble(0.0));
  ASSERT_EQ(scan->getScanSize(), 720u);
  for (size_t i = 0; i < scan->getScanSize(); ++i) EXPECT_FALSE(scan->getScanRangeValidity(i));
}

TEST(AnnotatedRawlog, MrptReadsBackTheMotionsTheScansAndTheirTimes) {
  test::TempDir folder("annotated");
  const std::string path = (folder.dir() / "drive.rawlog").string();
  // Four scans of a KITTI-like input (no MRPT observation): a drive that climbs and turns.
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 4; ++i)
    poses.push_back(poseFromXYZYPR(1.5 * i, 0.2 * i * i, 0.05 * i, 0.1 * i, 0.02 * i, -0.01 * i));
  const PointCloud scene = syntheticScene();
  {
    AnnotatedRawlogWriter writer(path);
    for (int i = 0; i < 4; ++i) {
      TimedScan scan;
      scan.timestamp = mrpt::Clock::fromDouble(1000.0 + 0.1 * i);
      scan.points = scene;
      writer.write(scan, poses[i], scan.points);
    }
    EXPECT_FALSE(fs::exists(path)) << "nothing appears before commit()";
    writer.commit();
    EXPECT_EQ(writer.count(), 4u);
  }
  mrpt::io::CFileGZInputStream in(path);
  auto archive = mrpt::serialization::archiveFrom(in);
  mrpt::obs::CActionCollection::Ptr actions;
  mrpt::obs::CSensoryFrame::Ptr frame;
  size_t entry = 0, scans = 0;
  mrpt::poses::CPose3D pose;
  while (mrpt::obs::CRawlog::readActionObservationPair(archive, actions, frame, entry)) {
    ASSERT_LT(scans, poses.size());
    const auto moved = actions->getActionByClass<mrpt::obs::CActionRobotMovement3D>();
    const auto moved2d = actions->getActionByClass<mrpt::obs::CActionRobotMovement2D>();
    ASSERT_TRUE(moved && moved2d);
    pose = pose + moved->poseChange.mean;
    const Eigen::Isometry3d expected = poses.front().inverse() * poses[scans];
    EXPECT_LT((toIsometry(pose).translation() - expected.translation()).norm(), 1e-9) << scans;
    EXPECT_TRUE(toIsometry(pose).linear().isApprox(expected.linear(), 1e-9)) << scans;
    EXPECT_NEAR(mrpt::Clock::toDouble(moved->timestamp), 1000.0 + 0.1 * scans, 1e-6);
    // A 5 cm, half-degree standard deviation per axis unless told otherwise (MRPT's x, y, z
    // take a little of the rotation's share).
    EXPECT_NEAR(moved->poseChange.cov(0, 0), 0.05 * 0.05, 1e-4);
    EXPECT_NEAR(moved->poseChange.cov(3, 3), std::pow(0.5 * M_PI / 180.0, 2), 1e-6);
    const auto cloud = frame->getObservationByClass<mrpt::obs::CObservationPointCloud>();
    ASSERT_TRUE(cloud);
    EXPECT_EQ(cloud->pointcloud->size(), scene.size());
    EXPECT_EQ(cloud->sensorLabel, "LIDAR");
    ASSERT_TRUE(frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>());
    ++scans;
  }
  EXPECT_EQ(scans, poses.size());
}

TEST(AnnotatedRawlog, AWriterDroppedBeforeCommitKeepsWhatItWroteAsPartial) {
  test::TempDir folder("annotated_partial");
  const std::string path = (folder.dir() / "drive.rawlog").string();
  {
    AnnotatedRawlogWriter writer(path);
    TimedScan scan;
    scan.points = syntheticScene();
    writer.write(scan, Eigen::Isometry3d::Identity(), scan.points);
  }
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(fs::exists(path + ".partial"));
}

}  // namespace
}  // namespace dlo
