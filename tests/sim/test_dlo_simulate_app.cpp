// dlo-simulate end to end: the built binary, its rawlog read back through MRPT.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationVelodyneScan.h>
#include <mrpt/serialization/CArchive.h>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

}  // namespace

TEST(DloSimulate, WritesOneVelodyneScanAndOnePosePerFrameDeterministically) {
  const fs::path a = freshDir("a"), b = freshDir("b");
  ASSERT_EQ(runSimulator("--out " + a.string() + " --frames 3 --sensor VLP16 --quiet").status, 0);
  ASSERT_EQ(
      runSimulator("--out " + b.string() + " --frames 3 --sensor VLP16 --quiet --threads 1").status,
      0);
  EXPECT_EQ(slurp(a / "sequence.rawlog"), slurp(b / "sequence.rawlog"));
  EXPECT_EQ(slurp(a / "groundtruth.tum"), slurp(b / "groundtruth.tum"));
  EXPECT_FALSE(fs::exists(a / "sequence.rawlog.part"));

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
  using namespace dlo::sim;
  const auto world = ProceduralWorld::generate(4);
  const WorldParams layout;
  const Route route = Route::roundedRectangle(layout.loopMin, layout.loopMax, 10.0);
  const VehicleTrajectory traj(route, world.terrain());
  SweepSimulatorParams sp;
  sp.model = makeLidarModel(SensorType::HDL32);
  sp.seed = 4;
  const SweepSimulator sim(world, traj, sp);
  const Sweep s = sim.simulate(0);

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

TEST(DloSimulate, BadArgumentsAreOneSentenceAndExitStatusOne) {
  const std::string out = "--out " + freshDir("bad").string();
  RunResult r = runSimulator(out + " --sensor OS1");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--sensor"), std::string::npos) << r.err;
  r = runSimulator(out + " --frames 0");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--frames"), std::string::npos) << r.err;
  for (const char* hills : {" --hills 0.5", " --hills steep", " --hills"}) {
    r = runSimulator(out + hills);
    EXPECT_EQ(r.status, 1) << hills;
    EXPECT_NE(r.err.find("--hills"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  }
  r = runSimulator("--out /proc/dlo_simulate_cannot_write --frames 1");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("--out"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_EQ(runSimulator("--help > /dev/null").status, 0);
}

TEST(DloSimulate, DrivesAnOpenRoadOverHillsWithStops) {
  const fs::path dir = freshDir("conditions");
  ASSERT_EQ(runSimulator("--out " + dir.string() +
                         " --frames 2 --sensor VLP16 --open-road --hills 0.2 --stops --quiet")
                .status,
            0);
  std::ifstream tum(dir / "groundtruth.tum");
  std::string line;
  int poses = 0;
  while (std::getline(tum, line)) poses += line[0] != '#';
  EXPECT_EQ(poses, 2);
  EXPECT_GT(fs::file_size(dir / "sequence.rawlog"), 100000u);
}
