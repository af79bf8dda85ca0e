// dlo-kitti2rawlog, dlo-rawlog2kitti and dlo-pcap2rawlog end to end: the built binaries on the
// real samples and a short simulated drive, and their bad-input cases (non-zero exit, one line
// naming the file).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../test_process.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/kitti_scan_source.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "io_test_helpers.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

using test::readFile;
using test::RunResult;

RunResult run(const std::string& binary, const std::vector<std::string>& args,
              const test::TempDir& dir) {
  std::string cmd = test::shellQuote(binary);
  for (const auto& a : args) cmd += " " + test::shellQuote(a);
  const std::string out = dir.path("stdout.txt"), err = dir.path("stderr.txt");
  cmd += " >" + test::shellQuote(out) + " 2>" + test::shellQuote(err);
  RunResult r;
  const int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

/// Non-zero exit and exactly one line on stderr, starting with the program name and naming
/// `name`.
void expectOneLineError(const RunResult& r, const std::string& program, const std::string& name) {
  EXPECT_NE(r.status, 0);
  EXPECT_EQ(r.err.rfind(program + ": ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(name), std::string::npos) << r.err;
}

size_t countLines(const std::string& text) {
  return static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
}

/// A KITTI sequence folder from the first three real city scans, with times and poses (the
/// LiDAR moving 0.8 m forward per scan).
std::string makeSequence(const test::TempDir& dir) {
  const std::string seq = dir.path("seq");
  fs::create_directories(seq + "/velodyne");
  for (int i = 0; i < 3; ++i) {
    const std::string name = "00000" + std::to_string(i) + ".bin.gz";
    fs::copy_file(test::sharedData("kitti_city_seq/" + name), seq + "/velodyne/" + name);
  }
  std::ofstream(seq + "/times.txt") << "0.000000e+00\n1.036400e-01\n2.072800e-01\n";
  std::ofstream(seq + "/poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\n"
                                       "1 0 0 0 0 1 0 0 0 0 1 0.8\n"
                                       "1 0 0 0 0 1 0 0 0 0 1 1.6\n";
  return seq;
}

TEST(Kitti2Rawlog, ConvertsASequenceIntoAReadableRawlogAndTumGroundTruth) {
  test::TempDir dir;
  const std::string seq = makeSequence(dir);
  const RunResult r =
      run(DLO_KITTI2RAWLOG_BINARY, {seq, dir.path("out.rawlog"), "--gt", dir.path("gt.tum")}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("wrote 3 scans"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path("out.rawlog.tmp")));

  RawlogScanSource source(dir.path("out.rawlog"));
  TimedScan scan;
  size_t n = 0;
  while (source.next(scan)) {
    EXPECT_EQ(scan.sensor_label, "VELODYNE");
    EXPECT_EQ(scan.source_class, "CObservationPointCloud");
    EXPECT_GT(scan.points.size(), 100000u);
    ++n;
  }
  EXPECT_EQ(n, 3u);
  EXPECT_NEAR(scan.timestampSeconds(), 0.20728, 1e-6);
  EXPECT_TRUE(source.stats().error.empty());

  // Without calib.txt, poses.txt is already in the LiDAR frame: the z of the camera convention
  // is copied as is.
  std::istringstream tum(readFile(dir.path("gt.tum")));
  std::string line;
  std::vector<std::vector<double>> rows;
  while (std::getline(tum, line)) {
    std::istringstream in(line);
    std::vector<double> v(8);
    for (double& x : v) in >> x;
    rows.push_back(v);
  }
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_NEAR(rows[1][0], 0.10364, 1e-9);
  EXPECT_NEAR(rows[2][3], 1.6, 1e-9);
  EXPECT_NEAR(rows[2][7], 1.0, 1e-9);  // qw
}

TEST(Kitti2Rawlog, ConvertsCameraPosesWithCalib) {
  test::TempDir dir;
  const std::string seq = makeSequence(dir);
  std::ofstream(seq + "/calib.txt") << "P0: 7.2e+02 0 6.0e+02 0 0 7.2e+02 1.7e+02 0 0 0 1 0\n"
                                       "Tr: 0 -1 0 -0.01 0 0 -1 -0.07 1 0 0 -0.27\n";
  const RunResult r =
      run(DLO_KITTI2RAWLOG_BINARY,
          {seq, dir.path("out.rawlog"), "--gt", dir.path("gt.tum"), "--quiet"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_TRUE(r.err.empty());
  const std::string tum = readFile(dir.path("gt.tum"));
  ASSERT_EQ(countLines(tum), 3u);
  // Camera forward (z) 1.6 m = LiDAR forward (x) 1.6 m.
  std::istringstream in(tum.substr(tum.rfind('\n', tum.size() - 2) + 1));
  double t, x, y, z;
  in >> t >> x >> y >> z;
  EXPECT_NEAR(x, 1.6, 1e-9);
  EXPECT_NEAR(y, 0.0, 1e-9);
  EXPECT_NEAR(z, 0.0, 1e-9);
}

TEST(Kitti2Rawlog, NamesTheBadFileAndKeepsWhatWasConverted) {
  test::TempDir dir;
  const std::string seq = makeSequence(dir);
  std::ofstream(seq + "/velodyne/000003.bin", std::ios::binary) << std::string(17, 'x');
  std::ofstream(seq + "/times.txt", std::ios::app) << "0.3\n";
  std::ofstream(seq + "/poses.txt", std::ios::app) << "1 0 0 0 0 1 0 0 0 0 1 2.4\n";
  std::ofstream(dir.path("out.rawlog")) << "previous";
  const RunResult r = run(DLO_KITTI2RAWLOG_BINARY, {seq, dir.path("out.rawlog")}, dir);
  const std::string last_line = r.err.substr(r.err.rfind('\n', r.err.size() - 2) + 1);
  EXPECT_NE(r.status, 0);
  EXPECT_NE(last_line.find("000003.bin"), std::string::npos) << r.err;
  EXPECT_NE(last_line.find("multiple of 16"), std::string::npos) << r.err;
  EXPECT_EQ(readFile(dir.path("out.rawlog")), "previous");
  RawlogScanSource partial(dir.path("out.rawlog.partial"));
  TimedScan scan;
  size_t n = 0;
  while (partial.next(scan)) ++n;
  EXPECT_EQ(n, 3u);
}

TEST(Kitti2Rawlog, RejectsBadInputWithOneLineNamingTheFile) {
  test::TempDir dir;
  const std::string program = "dlo-kitti2rawlog";
  expectOneLineError(run(DLO_KITTI2RAWLOG_BINARY, {dir.path("nope"), dir.path("o.rawlog")}, dir),
                     program, "nope");
  fs::create_directories(dir.path("empty_seq"));
  expectOneLineError(
      run(DLO_KITTI2RAWLOG_BINARY, {dir.path("empty_seq"), dir.path("o.rawlog")}, dir), program,
      "velodyne/");
  const std::string seq = makeSequence(dir);
  std::ofstream(seq + "/times.txt") << "0.0\nzero point one\n0.2\n";
  expectOneLineError(run(DLO_KITTI2RAWLOG_BINARY, {seq, dir.path("o.rawlog"), "--quiet"}, dir),
                     program, "times.txt' line 2");
  std::ofstream(seq + "/times.txt") << "0.0\n0.1\n0.2\n";
  std::ofstream(seq + "/poses.txt") << "1 0 0 0 0 1 0 0 0 0 1 0\nnan\n";
  expectOneLineError(run(DLO_KITTI2RAWLOG_BINARY, {seq, dir.path("o.rawlog"), "--quiet"}, dir),
                     program, "poses.txt' line 2");
  fs::remove(seq + "/poses.txt");
  expectOneLineError(
      run(DLO_KITTI2RAWLOG_BINARY, {seq, dir.path("o.rawlog"), "--gt", dir.path("g.tum")}, dir),
      program, "poses.txt");
  EXPECT_FALSE(fs::exists(dir.path("o.rawlog")));
  const RunResult usage = run(DLO_KITTI2RAWLOG_BINARY, {seq}, dir);
  EXPECT_EQ(usage.status, 2);
  EXPECT_EQ(run(DLO_KITTI2RAWLOG_BINARY, {"--help"}, dir).status, 0);
}

TEST(Pcap2Rawlog, ConvertsTheRealCaptureIntoVelodyneScans) {
  test::TempDir dir;
  const RunResult r = run(DLO_PCAP2RAWLOG_BINARY,
                          {test::sharedData("sample_velodyne_vlp16_gps.pcap"), dir.path("v.rawlog"),
                           "--model", "VLP16"},
                          dir);
  ASSERT_EQ(r.status, 0) << r.err;
  RawlogScanSource source(dir.path("v.rawlog"));
  TimedScan scan;
  size_t n = 0;
  while (source.next(scan)) {
    EXPECT_EQ(scan.source_class, "CObservationVelodyneScan");
    EXPECT_EQ(scan.point_times.size(), scan.points.size());
    ++n;
  }
  EXPECT_GE(n, 3u);
  EXPECT_LE(n, 4u);
  EXPECT_TRUE(source.stats().error.empty());
}

TEST(Pcap2Rawlog, RejectsBadInputWithOneLineNamingTheFile) {
  test::TempDir dir;
  const std::string program = "dlo-pcap2rawlog";
  expectOneLineError(run(DLO_PCAP2RAWLOG_BINARY,
                         {dir.path("missing.pcap"), dir.path("o.rawlog"), "--model", "VLP16"}, dir),
                     program, "missing.pcap");
  std::ofstream(dir.path("text.pcap")) << "hello\n";
  expectOneLineError(run(DLO_PCAP2RAWLOG_BINARY,
                         {dir.path("text.pcap"), dir.path("o.rawlog"), "--model", "VLP16"}, dir),
                     program, "text.pcap");
  EXPECT_FALSE(fs::exists(dir.path("o.rawlog")));
  EXPECT_FALSE(fs::exists(dir.path("o.rawlog.tmp")));
  EXPECT_EQ(run(DLO_PCAP2RAWLOG_BINARY, {dir.path("text.pcap"), dir.path("o.rawlog")}, dir).status,
            2);
  EXPECT_EQ(run(DLO_PCAP2RAWLOG_BINARY, {"--help"}, dir).status, 0);
}

/// A 6-sweep simulated VLP-16 drive (sequence.rawlog, groundtruth.tum) in `dir`/sim.
std::string simulateDrive(const test::TempDir& dir) {
  const std::string sim = dir.path("sim");
  const RunResult r =
      run(DLO_SIMULATE_BINARY,
          {"--out", sim, "--frames", "6", "--sensor", "VLP16", "--seed", "1", "--quiet"}, dir);
  EXPECT_EQ(r.status, 0) << r.err;
  return sim;
}

TEST(Rawlog2Kitti, WritesAFolderThatReadsBackAsTheSameScansTimesAndGroundTruth) {
  test::TempDir dir;
  const std::string sim = simulateDrive(dir), kitti = dir.path("kitti");
  const RunResult r =
      run(DLO_RAWLOG2KITTI_BINARY,
          {sim + "/sequence.rawlog", kitti, "--gt", sim + "/groundtruth.tum", "--quiet"}, dir);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(kitti + ".tmp"));
  // The scans dlo-slam reads from the folder are those it reads from the rawlog, bit for bit.
  RawlogScanSource rawlog(sim + "/sequence.rawlog");
  KittiScanSource folder(kitti);
  TimedScan a, b;
  size_t scans = 0;
  while (rawlog.next(a)) {
    ASSERT_TRUE(folder.next(b)) << "scan " << scans;
    EXPECT_NEAR(b.timestampSeconds(), a.timestampSeconds(), 1e-6);
    ASSERT_EQ(b.points.size(), a.points.size());
    EXPECT_EQ(b.points, a.points) << "scan " << scans;
    ++scans;
  }
  EXPECT_FALSE(folder.next(b));
  EXPECT_EQ(scans, 6u);
  // poses.txt: the ground truth at each scan, in the first scan's frame.
  const metrics::Trajectory gt = metrics::readTumTrajectory(sim + "/groundtruth.tum");
  const std::vector<Eigen::Isometry3d>& poses = folder.sequence().lidar_poses;
  ASSERT_EQ(poses.size(), scans);
  ASSERT_GE(gt.size(), scans);
  EXPECT_TRUE(poses.front().isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  for (size_t i = 0; i < scans; ++i) {
    const Eigen::Isometry3d expected = gt.poses.front().inverse() * gt.poses[i];
    EXPECT_TRUE(poses[i].isApprox(expected, 1e-8)) << "pose " << i;
  }
  EXPECT_GT(poses.back().translation().norm(), 1.0) << "the simulated vehicle moves";
}

TEST(Rawlog2Kitti, RejectsBadInputWithOneLineNamingTheFile) {
  test::TempDir dir;
  const std::string program = "dlo-rawlog2kitti";
  expectOneLineError(run(DLO_RAWLOG2KITTI_BINARY, {dir.path("no.rawlog"), dir.path("k")}, dir),
                     program, "no.rawlog");
  EXPECT_FALSE(fs::exists(dir.path("k")));
  std::ofstream(dir.path("text.rawlog")) << "not a rawlog\n";
  expectOneLineError(run(DLO_RAWLOG2KITTI_BINARY, {dir.path("text.rawlog"), dir.path("k")}, dir),
                     program, "text.rawlog");
  const std::string sim = simulateDrive(dir);
  // A ground truth that misses the scans' times by a second.
  metrics::Trajectory late = metrics::readTumTrajectory(sim + "/groundtruth.tum");
  for (double& t : late.times) t += 1.0;
  metrics::writeTumTrajectory(dir.path("late.tum"), late);
  expectOneLineError(
      run(DLO_RAWLOG2KITTI_BINARY,
          {sim + "/sequence.rawlog", dir.path("k"), "--gt", dir.path("late.tum"), "--quiet"}, dir),
      program, "late.tum");
  EXPECT_FALSE(fs::exists(dir.path("k"))) << "no folder for a conversion that failed";
  // An output folder that already holds files is not overwritten.
  fs::create_directories(dir.path("full"));
  std::ofstream(dir.path("full/keep.txt")) << "mine\n";
  expectOneLineError(
      run(DLO_RAWLOG2KITTI_BINARY, {sim + "/sequence.rawlog", dir.path("full")}, dir), program,
      "full");
  EXPECT_EQ(readFile(dir.path("full/keep.txt")), "mine\n");
  EXPECT_EQ(run(DLO_RAWLOG2KITTI_BINARY, {sim + "/sequence.rawlog"}, dir).status, 2);
  EXPECT_EQ(run(DLO_RAWLOG2KITTI_BINARY,
                {sim + "/sequence.rawlog", dir.path("k"), "--max-frames", "0"}, dir)
                .status,
            2);
  EXPECT_EQ(run(DLO_RAWLOG2KITTI_BINARY, {"--help"}, dir).status, 0);
}

}  // namespace
}  // namespace dlo
