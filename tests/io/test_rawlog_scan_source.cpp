// RawlogScanSource: the real VLP-16 rawlog, both layouts, filters, skipped classes, broken files.
#include <gtest/gtest.h>

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "dlo/files/error.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/mrpt/rawlog_writer.h"
#include "dlo/mrpt/scan_file.h"
#include "io_test_helpers.h"

namespace dlo {
namespace {

using test::TempDir;

std::vector<TimedScan> readAll(RawlogScanSource& source) {
  std::vector<TimedScan> scans;
  TimedScan scan;
  while (source.next(scan)) scans.push_back(scan);
  return scans;
}

void expectSamePoints(const mrpt::maps::CPointsMap& map, const PointCloud& points) {
  ASSERT_EQ(points.size(), map.size());
  for (size_t i = 0; i < points.size(); i += 97) {
    float x, y, z;
    map.getPointFast(i, x, y, z);
    EXPECT_FLOAT_EQ(points[i].x(), x);
    EXPECT_FLOAT_EQ(points[i].y(), y);
    EXPECT_FLOAT_EQ(points[i].z(), z);
  }
}

TEST(RawlogScanSource, ReadsTheRealVlp16VelodyneScanWithPointTimes) {
  RawlogScanSource source(test::sharedData("test_velodyne_VLP16.rawlog"));
  const auto scans = readAll(source);
  ASSERT_EQ(scans.size(), 1u);
  const TimedScan& s = scans[0];
  EXPECT_EQ(s.source_class, "CObservationVelodyneScan");
  EXPECT_EQ(s.sensor_label, "Velodyne1_SCAN");
  EXPECT_EQ(s.beams, 16);
  EXPECT_GT(s.points.size(), 10000u);
  float zmin = 1e9f, zmax = -1e9f, rmax = 0;
  for (const auto& p : s.points) {
    zmin = std::min(zmin, p.z());
    zmax = std::max(zmax, p.z());
    rmax = std::max(rmax, p.norm());
  }
  EXPECT_LT(rmax, 130.0f);  // VLP-16: 100 m nominal range
  EXPECT_GT(zmax - zmin, 1.0f);
  EXPECT_LT(zmax - zmin, 30.0f);
  ASSERT_EQ(s.point_times.size(), s.points.size());
  const auto [tmin, tmax] = std::minmax_element(s.point_times.begin(), s.point_times.end());
  EXPECT_GE(*tmin, -0.01f);
  EXPECT_LT(*tmax - *tmin, 0.2f);  // one rotation at 5-20 Hz
  EXPECT_TRUE(source.stats().error.empty());
  EXPECT_EQ(source.stats().entries_read, 1u);
}

TEST(RawlogScanSource, ReadsObservationOnlyAndSensoryFrameLayoutsAlike) {
  TempDir dir;
  const auto map = test::kittiSubsample(10);
  {
    RawlogWriter w(dir.path("obs_only.rawlog"));
    for (int i = 0; i < 3; ++i) w.write(*test::pointCloudObservation(map, "VELODYNE", 10.0 + i));
    w.commit();
  }
  {
    test::RawObjectWriter w(dir.path("pairs.rawlog"));
    for (int i = 0; i < 3; ++i) {
      mrpt::obs::CActionCollection actions;
      mrpt::obs::CSensoryFrame sf;
      sf.insert(test::pointCloudObservation(map, "VELODYNE", 10.0 + i));
      w.write(actions);
      w.write(sf);
    }
  }
  for (const std::string name : {"obs_only.rawlog", "pairs.rawlog"}) {
    SCOPED_TRACE(name);
    RawlogScanSource source(dir.path(name));
    const auto scans = readAll(source);
    ASSERT_EQ(scans.size(), 3u);
    for (int i = 0; i < 3; ++i) {
      expectSamePoints(*map, scans[i].points);
      EXPECT_NEAR(scans[i].timestampSeconds(), 10.0 + i, 1e-6);
      EXPECT_EQ(scans[i].sensor_label, "VELODYNE");
      EXPECT_TRUE(scans[i].point_times.empty());
    }
    EXPECT_TRUE(source.stats().error.empty());
    EXPECT_TRUE(source.stats().skipped_by_class.empty());  // actions are layout, not skipped data
  }
}

TEST(RawlogScanSource, ReadsEntriesThatStraddleItsReadBuffer) {
  // The stream is read in 64 KiB chunks: 400 action-and-frame pairs of about 1.3 KiB each put
  // entry headers (which the reader peeks at) and observations across every chunk boundary, and
  // a large scan in the middle takes the path that bypasses the buffer.
  TempDir dir;
  const auto small = test::kittiSubsample(1500);
  const auto large = test::kittiSubsample(2);
  ASSERT_GT(large->size() * 12, 64u * 1024u);
  {
    test::RawObjectWriter w(dir.path("many.rawlog"));
    for (int i = 0; i < 400; ++i) {
      mrpt::obs::CActionCollection actions;
      mrpt::obs::CSensoryFrame sf;
      sf.insert(test::pointCloudObservation(i == 200 ? large : small, "L", 0.1 * i));
      w.write(actions);
      w.write(sf);
    }
  }
  RawlogScanSource source(dir.path("many.rawlog"));
  const auto scans = readAll(source);
  ASSERT_EQ(scans.size(), 400u);
  for (int i = 0; i < 400; ++i) {
    SCOPED_TRACE(i);
    expectSamePoints(i == 200 ? *large : *small, scans[i].points);
    EXPECT_NEAR(scans[i].timestampSeconds(), 0.1 * i, 1e-6);
  }
  EXPECT_TRUE(source.stats().error.empty()) << source.stats().error;
}

TEST(RawlogScanSource, AppliesTheSensorPose) {
  TempDir dir;
  const auto map = test::kittiSubsample(50);
  auto obs = test::pointCloudObservation(map, "L", 1.0);
  obs->sensorPose = mrpt::poses::CPose3D(1.0, 2.0, 3.0, M_PI / 2, 0, 0);
  {
    RawlogWriter w(dir.path("posed.rawlog"));
    w.write(*obs);
    w.commit();
  }
  RawlogScanSource source(dir.path("posed.rawlog"));
  TimedScan scan;
  ASSERT_TRUE(source.next(scan));
  float x, y, z;
  map->getPointFast(0, x, y, z);
  // Yaw 90 degrees: (x, y) -> (-y, x), then the translation.
  EXPECT_NEAR(scan.points[0].x(), -y + 1.0f, 1e-4);
  EXPECT_NEAR(scan.points[0].y(), x + 2.0f, 1e-4);
  EXPECT_NEAR(scan.points[0].z(), z + 3.0f, 1e-4);
}

TEST(RawlogScanSource, KeepsOnlyTheRequestedSensorLabel) {
  TempDir dir;
  const auto map = test::kittiSubsample(50);
  {
    RawlogWriter w(dir.path("two_sensors.rawlog"));
    for (int i = 0; i < 4; ++i) {
      w.write(*test::pointCloudObservation(map, i % 2 ? "REAR" : "FRONT", i));
    }
    w.commit();
  }
  ScanSourceOptions options;
  options.sensor_label = "REAR";
  RawlogScanSource source(dir.path("two_sensors.rawlog"), options);
  const auto scans = readAll(source);
  ASSERT_EQ(scans.size(), 2u);
  for (const auto& s : scans) EXPECT_EQ(s.sensor_label, "REAR");
  EXPECT_EQ(source.stats().skipped_by_label, 2u);
}

TEST(RawlogScanSource, DropsPointsOutsideTheRangeLimits) {
  TempDir dir;
  const auto map = test::kittiSubsample(10);
  {
    RawlogWriter w(dir.path("one.rawlog"));
    w.write(*test::pointCloudObservation(map, "VELODYNE", 0));
    w.commit();
  }
  ScanSourceOptions options;
  options.min_range = 5.0;
  options.max_range = 20.0;
  RawlogScanSource source(dir.path("one.rawlog"), options);
  TimedScan scan;
  ASSERT_TRUE(source.next(scan));
  size_t expected = 0;
  for (size_t i = 0; i < map->size(); ++i) {
    float x, y, z;
    map->getPointFast(i, x, y, z);
    const float r = std::sqrt(x * x + y * y + z * z);
    if (r >= 5.0f && r <= 20.0f) ++expected;
  }
  EXPECT_EQ(scan.points.size(), expected);
  EXPECT_EQ(scan.dropped_by_range, map->size() - expected);
  EXPECT_GT(scan.dropped_by_range, 0u);
  for (const auto& p : scan.points) {
    EXPECT_GE(p.norm(), 5.0f - 1e-3f);
    EXPECT_LE(p.norm(), 20.0f + 1e-3f);
  }
}

TEST(RawlogScanSource, DropsAndCountsNonFinitePoints) {
  TempDir dir;
  auto map = mrpt::maps::CSimplePointsMap::Create();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  map->insertPointFast(1, 2, 3);
  map->insertPointFast(nan, 2, 3);
  map->insertPointFast(4, inf, 3);
  map->insertPointFast(5, 6, 7);
  {
    RawlogWriter w(dir.path("nan.rawlog"));
    w.write(*test::pointCloudObservation(map, "L", 0));
    w.commit();
  }
  RawlogScanSource source(dir.path("nan.rawlog"));
  TimedScan scan;
  ASSERT_TRUE(source.next(scan));
  EXPECT_EQ(scan.points.size(), 2u);
  EXPECT_EQ(scan.dropped_non_finite, 2u);
  EXPECT_EQ(source.stats().dropped_non_finite, 2u);
}

TEST(RawlogScanSource, SkipsAndCountsOtherClassesAndEmptyScans) {
  TempDir dir;
  const auto map = test::kittiSubsample(50);
  {
    RawlogWriter w(dir.path("mixed.rawlog"));
    w.write(*test::pointCloudObservation(map, "L", 0));
    mrpt::obs::CObservationOdometry odo;
    w.write(odo);
    w.write(odo);
    mrpt::obs::CObservationRotatingScan rot;
    w.write(rot);
    w.write(*test::pointCloudObservation(mrpt::maps::CSimplePointsMap::Create(), "L", 1));
    w.write(*test::pointCloudObservation(map, "L", 2));
    w.commit();
  }
  RawlogScanSource source(dir.path("mixed.rawlog"));
  const auto scans = readAll(source);
  EXPECT_EQ(scans.size(), 2u);
  const ScanSourceStats& st = source.stats();
  EXPECT_EQ(st.entries_read, 6u);
  EXPECT_EQ(st.skipped_by_class.at("CObservationOdometry"), 2u);
  EXPECT_EQ(st.skipped_by_class.at("CObservationRotatingScan"), 1u);
  EXPECT_NE(st.skip_reasons.at("CObservationRotatingScan").find("elevation"), std::string::npos);
  EXPECT_EQ(st.empty_scans, 1u);
  const std::string summary = describeScanSourceStats(st);
  EXPECT_NE(summary.find("CObservationOdometry: 2"), std::string::npos) << summary;
  EXPECT_EQ(scans[1].entry_index, 5u);
  EXPECT_EQ(scans[0].beams, 0);  // A point cloud does not say.
}

TEST(RawlogScanSource, ReadsAnOusterRangeImageWithItsColumnTimesAndBeamCount) {
  // 64 beams x 8 columns, every return at 10 m, turning clockwise from 0.5 rad over 0.07 s.
  mrpt::obs::CObservationRotatingScan rot;
  rot.lidarModel = "OS1-64";
  rot.rowCount = 64;
  rot.columnCount = 8;
  rot.rangeResolution = 0.002;
  rot.rangeImage.setConstant(64, 8, 5000);
  rot.rangeImage(3, 2) = 0;  // no return
  rot.startAzimuth = 0.5;
  rot.azimuthSpan = -0.7;
  rot.sweepDuration = 0.07;
  mrpt::obs::CObservationRotatingScan unknown = rot;
  unknown.lidarModel = "VLP-16";
  TempDir dir;
  {
    RawlogWriter w(dir.path("ouster.rawlog"));
    w.write(rot);
    w.write(unknown);
    w.commit();
  }
  RawlogScanSource source(dir.path("ouster.rawlog"));
  const auto scans = readAll(source);
  ASSERT_EQ(scans.size(), 1u);
  const TimedScan& s = scans[0];
  EXPECT_EQ(s.source_class, "CObservationRotatingScan");
  EXPECT_EQ(s.beams, 64);
  ASSERT_EQ(s.points.size(), 64u * 8u - 1u);
  ASSERT_EQ(s.point_times.size(), s.points.size());
  // Column by column, beam 0 (the highest) first.
  size_t k = 0;
  for (int c = 0; c < 8; ++c) {
    for (int r = 0; r < 64; ++r) {
      if (r == 3 && c == 2) continue;
      const Eigen::Vector3f& p = s.points[k];
      EXPECT_NEAR(p.norm(), 10.0f, 1e-4f);
      EXPECT_NEAR(std::atan2(p.y(), p.x()), 0.5 - 0.1 * c, 1e-5) << c;
      EXPECT_NEAR(std::asin(p.z() / p.norm()) * 180.0 / M_PI, 22.5 - r * 45.0 / 63.0, 1e-3) << r;
      EXPECT_NEAR(s.point_times[k], 0.01 * c, 1e-6) << c;
      ++k;
    }
  }
  // No elevation table for other models in MRPT 2.5: skipped with the reason.
  EXPECT_EQ(source.stats().skipped_by_class.at("CObservationRotatingScan"), 1u);
  EXPECT_NE(source.stats().skip_reasons.at("CObservationRotatingScan").find("OS1-<rows>"),
            std::string::npos);
}

TEST(RawlogScanSource, ReadsPointsOfA3DRangeScan) {
  TempDir dir;
  mrpt::obs::CObservation3DRangeScan r3d;
  r3d.resizePoints3DVectors(3);  // also sizes the pixel indices serialization checks
  r3d.hasPoints3D = true;
  r3d.points3D_x = {1, 2, 3};
  r3d.points3D_y = {0, 0, 0};
  r3d.points3D_z = {0, 1, 2};
  r3d.sensorLabel = "CAM";
  {
    RawlogWriter w(dir.path("r3d.rawlog"));
    w.write(r3d);
    w.commit();
  }
  RawlogScanSource source(dir.path("r3d.rawlog"));
  TimedScan scan;
  ASSERT_TRUE(source.next(scan));
  EXPECT_EQ(scan.points.size(), 3u);
  EXPECT_EQ(scan.source_class, "CObservation3DRangeScan");
}

TEST(RawlogScanSource, StopsAtATruncationAndSaysWhere) {
  TempDir dir;
  const auto map = test::kittiSubsample(20);
  {
    RawlogWriter w(dir.path("full.rawlog"));
    for (int i = 0; i < 4; ++i) w.write(*test::pointCloudObservation(map, "L", i));
    w.commit();
  }
  // Cut in the middle of the third entry (entries are of equal size).
  const auto size = std::filesystem::file_size(dir.path("full.rawlog"));
  std::filesystem::copy_file(dir.path("full.rawlog"), dir.path("cut.rawlog"));
  std::filesystem::resize_file(dir.path("cut.rawlog"), size / 2 + size / 8);
  RawlogScanSource source(dir.path("cut.rawlog"));
  const auto scans = readAll(source);
  EXPECT_EQ(scans.size(), 2u);
  const std::string& error = source.stats().error;
  EXPECT_NE(error.find("corrupt at entry 2"), std::string::npos) << error;
  EXPECT_NE(error.find("byte offset " + std::to_string(size / 2)), std::string::npos) << error;
  EXPECT_NE(error.find("cut.rawlog"), std::string::npos) << error;

  // loadScanFile still gets the first scan of a truncated rawlog.
  EXPECT_EQ(loadScanFile(dir.path("cut.rawlog")).size(), map->size());
}

TEST(RawlogScanSource, ReportsARawlogCutInsideItsFirstEntryAsCorrupt) {
  TempDir dir;
  {
    RawlogWriter w(dir.path("one.rawlog"));
    w.write(*test::pointCloudObservation(test::kittiSubsample(20), "L", 0));
    w.commit();
  }
  std::filesystem::resize_file(dir.path("one.rawlog"), 1000);
  RawlogScanSource source(dir.path("one.rawlog"));
  TimedScan scan;
  EXPECT_FALSE(source.next(scan));
  EXPECT_NE(source.stats().error.find("corrupt at entry 0"), std::string::npos);
  try {
    loadScanFile(dir.path("one.rawlog"));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt at entry 0"), std::string::npos) << e.what();
  }
}

TEST(RawlogScanSource, RejectsFilesThatAreNotRawlogs) {
  TempDir dir;
  std::ofstream(dir.path("text.rawlog")) << "this is not a rawlog\n";
  EXPECT_THROW(RawlogScanSource(dir.path("text.rawlog")), InputError);
  EXPECT_THROW(RawlogScanSource(dir.path("missing.rawlog")), InputError);
  try {
    RawlogScanSource source(dir.path("text.rawlog"));
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("text.rawlog"), std::string::npos);
  }
}

TEST(RawlogScanSource, ReadsGzipCompressedRawlogs) {
  TempDir dir;
  const auto map = test::kittiSubsample(20);
  {
    RawlogWriter w(dir.path("small.rawlog.gz"));
    w.write(*test::pointCloudObservation(map, "L", 0));
    w.write(*test::pointCloudObservation(map, "L", 1));
    w.commit();
  }
  RawlogScanSource source(dir.path("small.rawlog.gz"));
  EXPECT_EQ(readAll(source).size(), 2u);
  EXPECT_TRUE(source.stats().error.empty());
}

TEST(RawlogWriter, KeepsWhatWasWrittenWhenNotCommitted) {
  TempDir dir;
  std::ofstream(dir.path("out.rawlog")) << "previous";
  {
    RawlogWriter w(dir.path("out.rawlog"));
    w.write(*test::pointCloudObservation(test::kittiSubsample(50), "L", 0));
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path("out.rawlog.partial")));
  EXPECT_FALSE(std::filesystem::exists(dir.path("out.rawlog.tmp")));
  std::ifstream in(dir.path("out.rawlog"));
  std::string previous;
  in >> previous;
  EXPECT_EQ(previous, "previous");
  RawlogScanSource source(dir.path("out.rawlog.partial"));
  EXPECT_EQ(readAll(source).size(), 1u);
}

}  // namespace
}  // namespace dlo
