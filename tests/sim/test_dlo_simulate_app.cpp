// dlo-simulate end to end: the built binary, its rawlog read back through MRPT.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/obs/CObservationRotatingScan.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/serialization/CArchive.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "dlo/core/sweep_timing.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"

namespace fs = std::filesystem;

namespace {

struct RunResult {
  int status = -1;
  std::string err;
};

RunResult runSimulator(const std::string& args) {
  // One file per test: ctest runs the tests of this binary in parallel processes.
  const fs::path errFile = fs::path(testing::TempDir()) /
                           (std::string("dlo_simulate_stderr_") +
                            testing::UnitTest::GetInstance()->current_test_info()->name() + ".txt");
  const std::string cmd = std::string(DLO_SIMULATE_BINARY) + " " + args + " 2> " + errFile.string();
  RunResult r;
  const int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  std::ifstream in(errFile);
  std::stringstream ss;
  ss << in.rdbuf();
  r.err = ss.str();
  return r;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::path(testing::TempDir()) / ("dlo_simulate_" + name);
  fs::remove_all(d);
  return d;
}

/// The simulator dlo-simulate runs for `sensor`, `seed`, --sweep-start and --spin with its
/// default route, in process.
struct InProcessSimulation {
  InProcessSimulation(dlo::sim::SensorType sensor, uint32_t seed, double sweepStartDeg = 0.0,
                      int spinDirection = -1)
      : world(dlo::sim::ProceduralWorld::generate(seed)),
        route(dlo::sim::Route::roundedRectangle(layout.loopMin, layout.loopMax, 10.0)),
        trajectory(route, world.terrain()),
        simulator(world, trajectory, parameters(sensor, seed, sweepStartDeg, spinDirection)) {}
  static dlo::sim::SweepSimulatorParams parameters(dlo::sim::SensorType sensor, uint32_t seed,
                                                   double sweepStartDeg, int spinDirection) {
    dlo::sim::SweepSimulatorParams p;
    p.model = dlo::sim::makeLidarModel(sensor);
    p.model.sweepStartDeg = sweepStartDeg;
    p.model.spinDirection = spinDirection;
    p.seed = seed;
    return p;
  }
  dlo::sim::ProceduralWorld world;
  dlo::sim::WorldParams layout;
  dlo::sim::Route route;
  dlo::sim::VehicleTrajectory trajectory;
  dlo::sim::SweepSimulator simulator;
};

/// Circular mean azimuth of points [first, last) of `map`, degrees counter-clockwise from +x.
double meanAzimuthDeg(const mrpt::maps::CPointsMap& map, size_t first, size_t last) {
  double sx = 0, sy = 0;
  for (size_t i = first; i < last; ++i) {
    float x, y, z;
    map.getPointFast(i, x, y, z);
    const double a = std::atan2(y, x);
    sx += std::cos(a);
    sy += std::sin(a);
  }
  return std::atan2(sy, sx) * 180.0 / M_PI;
}

}  // namespace

TEST(DloSimulate, WritesOneVelodyneScanAndOnePosePerFrameDeterministically) {
  const fs::path a = freshDir("a"), b = freshDir("b");
  ASSERT_EQ(runSimulator("--out " + a.string() + " --frames 3 --sensor VLP16 --quiet").status, 0);
  ASSERT_EQ(
      runSimulator("--out " + b.string() + " --frames 3 --sensor VLP16 --quiet --threads 1").status,
      0);
  EXPECT_EQ(slurp(a / "sequence.rawlog"), slurp(b / "sequence.rawlog"));
  EXPECT_EQ(slurp(a / "groundtruth.tum"), slurp(b / "groundtruth.tum"));
  EXPECT_FALSE(fs::exists(a / "sequence.rawlog.tmp"));

  // TUM: a comment header, then one line of 8 numbers per frame.
  std::ifstream tum(a / "groundtruth.tum");
  std::string line;
  ASSERT_TRUE(std::getline(tum, line));
  EXPECT_EQ(line[0], '#');
  int poses = 0;
  std::vector<double> stamps;
  while (std::getline(tum, line)) {
    std::istringstream in(line);
    double v[8];
    for (double& x : v) ASSERT_TRUE(in >> x) << line;
    stamps.push_back(v[0]);
    ++poses;
  }
  EXPECT_EQ(poses, 3);

  // The rawlog: observation-only, one CObservationVelodyneScan per frame, decodable by MRPT.
  mrpt::io::CFileGZInputStream f((a / "sequence.rawlog").string());
  auto arch = mrpt::serialization::archiveFrom(f);
  int count = 0;
  for (;;) {
    mrpt::serialization::CSerializable::Ptr o;
    try {
      o = arch.ReadObject();
    } catch (const std::exception&) {
      break;  // End of file.
    }
    auto velo = std::dynamic_pointer_cast<mrpt::obs::CObservationVelodyneScan>(o);
    ASSERT_TRUE(velo);
    EXPECT_EQ(velo->sensorLabel, "LIDAR");
    EXPECT_NEAR(velo->sensorPose.z(), 1.8, 1e-9);
    EXPECT_NEAR(mrpt::Clock::toDouble(velo->timestamp), stamps.at(count), 1e-6);
    // Stored decoded, with ring and time per point: no need to call generatePointCloud().
    EXPECT_GT(velo->point_cloud.size(), 10000u);
    EXPECT_EQ(velo->point_cloud.timestamp.size(), velo->point_cloud.size());
    EXPECT_EQ(velo->point_cloud.laser_id.size(), velo->point_cloud.size());
    EXPECT_GT(velo->scan_packets.size(), 70u);
    EXPECT_EQ(velo->calibration.laser_corrections.size(), 16u);
    // Within the sweep: one revolution of whole packets (a VLP-16 packet lasts 1.33 ms).
    for (const auto& ts : velo->point_cloud.timestamp) {
      const double dt = std::chrono::duration<double>(ts - velo->timestamp).count();
      ASSERT_GE(dt, 0.0);
      ASSERT_LT(dt, 0.1 + 0.0014);
    }
    ++count;
  }
  EXPECT_EQ(count, 3);
}

TEST(DloSimulate, StoresTheSimulatedPointsWithTheirFiringTimesAndPacketsThatDecodeToThem) {
  const fs::path dir = freshDir("decode");
  ASSERT_EQ(
      runSimulator("--out " + dir.string() + " --frames 1 --sensor HDL32 --seed 4 --quiet").status,
      0);
  mrpt::io::CFileGZInputStream f((dir / "sequence.rawlog").string());
  auto velo = std::dynamic_pointer_cast<mrpt::obs::CObservationVelodyneScan>(
      mrpt::serialization::archiveFrom(f).ReadObject());
  ASSERT_TRUE(velo);

  // The same sweep, in process.
  const InProcessSimulation in(dlo::sim::SensorType::HDL32, 4);
  const dlo::sim::SweepSimulator& sim = in.simulator;
  const dlo::sim::Sweep s = sim.simulate(0);

  // Stored points: firing-major, laser-minor, at their own firing time.
  const auto& pc = velo->point_cloud;
  size_t k = 0;
  for (int fi = 0; fi < s.firings; ++fi) {
    for (int l = 0; l < s.lasers; ++l) {
      if (s.range[s.index(fi, l)] <= 0) continue;
      ASSERT_LT(k, pc.size());
      const Eigen::Vector3d q = sim.sensorPoint(s, fi, l);
      ASSERT_LT((Eigen::Vector3d(pc.x[k], pc.y[k], pc.z[k]) - q).norm(), 1e-4);
      ASSERT_EQ(pc.laser_id[k], l);
      // In MRPT clock ticks (100 ns): absolute times as doubles would lose the precision.
      const auto ticks = (pc.timestamp[k] - velo->timestamp).count();
      ASSERT_NEAR(static_cast<double>(ticks),
                  (sim.pointTimeNs(s, fi, l) - s.referenceTimeNs) / 100.0, 1.0);
      ++k;
    }
  }
  EXPECT_EQ(k, pc.size());

  // The packets decode to the same returns, within 2 mm range and 0.01 deg azimuth units.
  // MRPT 2.5 decodes only the first 16 of the 32 returns of a block (lasers 0-15 of each
  // HDL-32 firing); a complete decoder yields all of them.
  mrpt::obs::CObservationVelodyneScan copy = *velo;
  mrpt::obs::CObservationVelodyneScan::TGeneratePointCloudParameters p;
  p.minDistance = 0.0f;
  copy.generatePointCloud(p);
  const auto& dec = copy.point_cloud;
  const auto expectedCount = [&](int lasersPerFiring) {
    size_t n = 0;
    for (int fi = 0; fi < s.firings; ++fi)
      for (int l = 0; l < lasersPerFiring; ++l) n += s.range[s.index(fi, l)] > 0;
    return n;
  };
  const int decodedLasers = dec.size() == expectedCount(32) ? 32 : 16;
  ASSERT_EQ(dec.size(), expectedCount(decodedLasers));
  k = 0;
  double worst = 0;
  for (int fi = 0; fi < s.firings; ++fi) {
    for (int l = 0; l < decodedLasers; ++l) {
      if (s.range[s.index(fi, l)] <= 0) continue;
      const Eigen::Vector3d q = sim.sensorPoint(s, fi, l);
      const Eigen::Vector3d d(dec.x[k], dec.y[k], dec.z[k]);
      worst = std::max(worst, (d - q).norm() / (0.004 + q.norm() * 4e-4));
      ++k;
    }
  }
  EXPECT_LT(worst, 1.0);
}

TEST(DloSimulate, WritesOusterSweepsAsRangeImagesThatTheReaderTurnsIntoTheSimulatedPoints) {
  struct Case {
    std::string options;
    double start;
    int spin;
  };
  for (const Case& c : {Case{"", 0.0, -1}, Case{"--sweep-start 90 --spin ccw", 90.0, 1}}) {
    SCOPED_TRACE(c.options);
    const fs::path dir = freshDir("ouster");
    ASSERT_EQ(runSimulator("--out " + dir.string() + " --frames 1 --sensor OS64 --seed 4 " +
                           c.options + " --quiet")
                  .status,
              0);
    {
      mrpt::io::CFileGZInputStream f((dir / "sequence.rawlog").string());
      auto rot = std::dynamic_pointer_cast<mrpt::obs::CObservationRotatingScan>(
          mrpt::serialization::archiveFrom(f).ReadObject());
      ASSERT_TRUE(rot);
      EXPECT_EQ(rot->lidarModel, "OS1-64");
      EXPECT_EQ(rot->rowCount, 64);
      EXPECT_EQ(rot->columnCount, 1024);
      EXPECT_NEAR(rot->sensorPose.z(), 1.8, 1e-9);
    }
    dlo::RawlogScanSource source((dir / "sequence.rawlog").string());
    dlo::TimedScan scan;
    ASSERT_TRUE(source.next(scan));
    EXPECT_EQ(scan.beams, 64);
    ASSERT_EQ(scan.point_times.size(), scan.points.size());

    // The same sweep in process: every return, column by column, at its column's time, within
    // the 2 mm range units of the range image.
    const InProcessSimulation in(dlo::sim::SensorType::OS64, 4, c.start, c.spin);
    const dlo::sim::Sweep s = in.simulator.simulate(0);
    const Eigen::Isometry3d mount = in.trajectory.sensorMount();
    size_t k = 0;
    for (int fi = 0; fi < s.firings; ++fi) {
      for (int l = 0; l < s.lasers; ++l) {
        if (s.range[s.index(fi, l)] <= 0) continue;
        ASSERT_LT(k, scan.points.size());
        const Eigen::Vector3d q = mount * in.simulator.sensorPoint(s, fi, l);
        ASSERT_LT((scan.points[k].cast<double>() - q).norm(), 1.5e-3) << fi << " " << l;
        ASSERT_NEAR(scan.point_times[k],
                    (in.simulator.pointTimeNs(s, fi, l) - s.referenceTimeNs) * 1e-9, 1e-6);
        ++k;
      }
    }
    EXPECT_EQ(k, scan.points.size());
    EXPECT_FALSE(source.next(scan));
  }
}

TEST(DloSimulate, UntimedSweepsStartAtTheGivenAzimuthAndTurnInTheGivenDirection) {
  struct Case {
    std::string options;
    double start;  // degrees counter-clockwise from forward
    int spin;      // -1 clockwise
  };
  for (const Case& c : {Case{"", 0.0, -1}, Case{"--sweep-start 90 --spin ccw", 90.0, 1},
                        Case{"--sweep-start=-120 --spin=cw", -120.0, -1}}) {
    SCOPED_TRACE(c.options);
    const fs::path dir = freshDir("untimed");
    ASSERT_EQ(runSimulator("--out " + dir.string() +
                           " --frames 2 --sensor VLP16 --no-point-times " + c.options + " --quiet")
                  .status,
              0);
    // Stored in firing order: the first firing (16 points) at the start azimuth, an eighth of
    // the sweep later about 45 deg further in the spin direction.
    mrpt::io::CFileGZInputStream f((dir / "sequence.rawlog").string());
    auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationPointCloud>(
        mrpt::serialization::archiveFrom(f).ReadObject());
    ASSERT_TRUE(obs);
    const auto& map = *obs->pointcloud;
    EXPECT_NEAR(std::remainder(meanAzimuthDeg(map, 0, 16) - c.start, 360.0), 0.0, 0.5);
    const size_t eighth = map.size() / 8;
    EXPECT_NEAR(std::remainder(meanAzimuthDeg(map, eighth, eighth + 16) - c.start, 360.0),
                c.spin * 45.0, 20.0);

    // dlo-slam's sweep timing reads the same direction and start off the order of the points,
    // as it gets them (vehicle frame), for both sweeps.
    dlo::RawlogScanSource source((dir / "sequence.rawlog").string());
    dlo::TimedScan scan;
    for (int k = 0; k < 2; ++k) {
      ASSERT_TRUE(source.next(scan));
      EXPECT_TRUE(scan.point_times.empty());
      std::vector<float> times;
      const dlo::SweepTimingEstimate e = dlo::estimateSweepTimes(scan.points, {}, times);
      EXPECT_TRUE(e.from_order);
      EXPECT_EQ(e.direction, c.spin);
      // The second sweep's first packet begins 0.86 ms (3.1 deg) into its revolution, and the
      // seam is put halfway across the 1.7 deg its packets leave open: 2.3 deg. The points are
      // seen from the vehicle's origin, 0.3 m behind the sensor: a few degrees of parallax on
      // the nearest ground when the start is to a side.
      EXPECT_NEAR(std::remainder(e.start_azimuth_deg - c.start, 360.0), k * c.spin * 2.3, 3.0);
    }
  }
}

TEST(DloSimulate, BadArgumentsAreOneSentenceAndExitStatusTwo) {
  const std::string out = "--out " + freshDir("bad").string();
  RunResult r = runSimulator(out + " --sensor OS1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--sensor"), std::string::npos) << r.err;
  r = runSimulator(out + " --frames 0");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--frames"), std::string::npos) << r.err;
  for (const char* hills : {" --hills 0.5", " --hills steep", " --hills"}) {
    r = runSimulator(out + hills);
    EXPECT_EQ(r.status, 2) << hills;
    EXPECT_NE(r.err.find("--hills"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  for (const std::string bad : {"--spin up", "--spin", "--sweep-start 400", "--sweep-start x"}) {
    r = runSimulator(out + " " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find(bad.substr(0, bad.find(' '))), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  r = runSimulator(out + " --bogus");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--bogus"), std::string::npos) << r.err;
  // An output that cannot be written is not a command-line mistake: exit status 1.
  r = runSimulator("--out /proc/dlo_simulate_cannot_write --frames 1");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(runSimulator("--help > /dev/null").status, 0);
}

TEST(DloSimulate, DrivesAnOpenRoadOverHillsWithStopsDeterministically) {
  const fs::path a = freshDir("conditions_a"), b = freshDir("conditions_b");
  const std::string options = " --frames 2 --sensor VLP16 --open-road --hills 0.2 --stops --quiet";
  ASSERT_EQ(runSimulator("--out " + a.string() + options).status, 0);
  ASSERT_EQ(runSimulator("--out " + b.string() + options + " --threads 1").status, 0);
  EXPECT_EQ(slurp(a / "sequence.rawlog"), slurp(b / "sequence.rawlog"));
  EXPECT_EQ(slurp(a / "groundtruth.tum"), slurp(b / "groundtruth.tum"));
  std::ifstream tum(a / "groundtruth.tum");
  std::string line;
  int poses = 0;
  while (std::getline(tum, line)) poses += line[0] != '#';
  EXPECT_EQ(poses, 2);
  EXPECT_GT(fs::file_size(a / "sequence.rawlog"), 100000u);
}
