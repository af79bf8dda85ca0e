// dlo-register end to end: the built binary on files written from the real HDL-64 scan.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_data.h"
#include "../test_process.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/units.h"
#include "dlo/formats/kitti_bin.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

using test::readFile;
using test::RunResult;

/// Temporary files of one test, removed with it.
class Workdir {
 public:
  Workdir() {
    const auto* info = testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(testing::TempDir()) /
           ("dlo_register_" + std::string(info->test_suite_name()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  ~Workdir() { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

 private:
  fs::path dir_;
};

RunResult runRegister(const std::vector<std::string>& args, const Workdir& wd) {
  std::string cmd = test::shellQuote(DLO_REGISTER_BINARY);
  for (const auto& a : args) cmd += " " + test::shellQuote(a);
  const std::string out = wd.path("stdout.txt"), err = wd.path("stderr.txt");
  cmd += " >" + test::shellQuote(out) + " 2>" + test::shellQuote(err);
  RunResult r;
  const int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = readFile(out);
  r.err = readFile(err);
  return r;
}

void writeKittiBin(const PointCloud& cloud, const std::string& path) {
  std::ofstream f(path, std::ios::binary);
  for (const auto& p : cloud) {
    const float v[4] = {p.x(), p.y(), p.z(), 0.0f};
    f.write(reinterpret_cast<const char*>(v), sizeof(v));
  }
}

void writeAsciiPly(const PointCloud& cloud, const std::string& path, bool with_intensity) {
  std::ofstream f(path);
  f << "ply\nformat ascii 1.0\nelement vertex " << cloud.size()
    << "\nproperty float x\nproperty float y\nproperty float z\n"
    << (with_intensity ? "property float intensity\n" : "") << "end_header\n";
  f.precision(9);
  for (const auto& p : cloud)
    f << p.x() << " " << p.y() << " " << p.z() << (with_intensity ? " 0\n" : "\n");
}

/// A number of the pose block: x, y, z, yaw_deg, pitch_deg, roll_deg.
double poseValue(const nlohmann::json& json, const char* key) {
  return json.at("pose").at(key).get<double>();
}

/// The 36 covariance entries, row-major; NaN where the output holds null (non-finite).
std::vector<double> covarianceOf(const nlohmann::json& json) {
  std::vector<double> values;
  for (const nlohmann::json& v : json.at("covariance")) {
    values.push_back(v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>());
  }
  return values;
}

int lineCount(const std::string& text) {
  return static_cast<int>(std::count(text.begin(), text.end(), '\n'));
}

/// Reference: even points; current: odd points seen from a frame moved by the truth.
class DloRegister : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
    test::splitEvenOdd(scan, even(), odd());
  }
  static PointCloud& even() {
    static PointCloud c;
    return c;
  }
  static PointCloud& odd() {
    static PointCloud c;
    return c;
  }

  /// Writes REF and CUR for `truth`, returning their paths.
  std::pair<std::string, std::string> writePair(const Eigen::Isometry3d& truth) {
    const std::string ref = wd_.path("ref.bin"), cur = wd_.path("cur.bin");
    writeKittiBin(even(), ref);
    writeKittiBin(test::expressIn(odd(), truth), cur);
    return {ref, cur};
  }

  /// A successful run printing exactly one JSON line, nothing on stderr; the line parsed.
  nlohmann::json expectJson(const std::vector<std::string>& args) {
    const RunResult r = runRegister(args, wd_);
    EXPECT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(lineCount(r.out), 1) << r.out;
    const nlohmann::json json = nlohmann::json::parse(r.out);
    EXPECT_TRUE(json.is_object()) << r.out;
    EXPECT_EQ(covarianceOf(json).size(), 36u) << r.out;
    return json;
  }

  /// A failed run: non-zero status, nothing on stdout, one line on stderr naming `what`.
  void expectError(const std::vector<std::string>& args, const std::string& what, int status = 1) {
    const RunResult r = runRegister(args, wd_);
    EXPECT_EQ(r.status, status) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(lineCount(r.err), 1) << r.err;
    EXPECT_EQ(r.err.rfind("dlo-register: ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << "expected '" << what << "' in: " << r.err;
  }

  void expectPose(const nlohmann::json& json, double x, double y, double z, double yaw_deg,
                  double pitch_deg, double roll_deg) {
    EXPECT_NEAR(poseValue(json, "x"), x, 0.03) << json;
    EXPECT_NEAR(poseValue(json, "y"), y, 0.03) << json;
    EXPECT_NEAR(poseValue(json, "z"), z, 0.03) << json;
    EXPECT_NEAR(poseValue(json, "yaw_deg"), yaw_deg, 0.1) << json;
    EXPECT_NEAR(poseValue(json, "pitch_deg"), pitch_deg, 0.1) << json;
    EXPECT_NEAR(poseValue(json, "roll_deg"), roll_deg, 0.1) << json;
  }

  Workdir wd_;
};

TEST_F(DloRegister, RecoversKnownMotionBetweenKittiFiles) {
  const auto [ref, cur] = writePair(poseFromXYZYPR(1.0, -0.5, 0.0, 5 * kDeg, 0, 0));
  const nlohmann::json json = expectJson({ref, cur});
  expectPose(json, 1.0, -0.5, 0.0, 5.0, 0.0, 0.0);
  EXPECT_EQ(json.at("converged"), true) << json;
  EXPECT_EQ(json.at("degenerate"), false) << json;
  EXPECT_GT(json.at("iterations").get<int>(), 0);
  EXPECT_GT(json.at("cells").get<int>(), 0);
  EXPECT_LT(json.at("rms_height_error").get<double>(), 0.2);
  for (const char* stage : {"grid", "gradients", "selection", "solve", "total"})
    EXPECT_GT(json.at("time_ms").at(stage).get<double>(), 0.0) << stage;
  const auto cov = covarianceOf(json);
  EXPECT_GT(cov[0], 0.0);       // x
  EXPECT_LT(cov[0], 1e-2);      // x observed
  EXPECT_GT(cov[2 * 7], 1e3);   // z not estimated in 3-DoF
  EXPECT_LT(cov[3 * 7], 1e-3);  // yaw observed (radians^2)
}

TEST_F(DloRegister, SixDofRecoversZPitchRoll) {
  const auto [ref, cur] =
      writePair(poseFromXYZYPR(0.5, -0.3, 0.05, 2 * kDeg, 0.5 * kDeg, -0.5 * kDeg));
  expectPose(expectJson({ref, cur, "--dof", "6"}), 0.5, -0.3, 0.05, 2.0, 0.5, -0.5);
}

TEST_F(DloRegister, InitIsInMetresAndDegrees) {
  // In 3-DoF, z, pitch and roll stay at the guess: the output shows how --init was read.
  const auto [ref, cur] =
      writePair(poseFromXYZYPR(1.0, -0.5, 0.05, 5 * kDeg, 0.5 * kDeg, -0.5 * kDeg));
  const nlohmann::json json = expectJson({ref, cur, "--init", "0.9 -0.4 0.05 4 0.5 -0.5"});
  expectPose(json, 1.0, -0.5, 0.05, 5.0, 0.5, -0.5);
  EXPECT_NEAR(poseValue(json, "pitch_deg"), 0.5, 1e-6);
  EXPECT_NEAR(poseValue(json, "roll_deg"), -0.5, 1e-6);
}

TEST_F(DloRegister, ConfigFileAndSetOverridesAreApplied) {
  const auto [ref, cur] = writePair(poseFromXYZYPR(0.2, 0.1, 0.0, 1 * kDeg, 0, 0));
  const std::string config = wd_.path("dlo.ini");
  std::ofstream(config) << "[grid]\nlevels = 2\n[solver]\nmax_iterations = 1\n";
  // One iteration per level: at most 2 in all.
  EXPECT_LE(expectJson({ref, cur, "--config", config}).at("iterations").get<int>(), 2);
  // --set wins over the file.
  EXPECT_LE(expectJson({ref, cur, "--config", config, "--set", "grid.levels=1"})
                .at("iterations")
                .get<int>(),
            1);
  // --dof wins over the file's solver.dof.
  std::ofstream(config) << "[solver]\ndof = 6\n";
  const nlohmann::json json = expectJson({ref, cur, "--config", config, "--dof", "3"});
  EXPECT_EQ(poseValue(json, "pitch_deg"), 0.0) << json;  // untouched in 3-DoF
}

TEST_F(DloRegister, ReadsPlyInput) {
  const std::string ref = wd_.path("ref.ply"), cur = wd_.path("cur.bin");
  writeAsciiPly(even(), ref, true);
  writeKittiBin(test::expressIn(odd(), poseFromXYZYPR(1.0, -0.5, 0, 5 * kDeg, 0, 0)), cur);
  expectPose(expectJson({ref, cur}), 1.0, -0.5, 0.0, 5.0, 0.0, 0.0);
}

TEST_F(DloRegister, ReadsPlyWithoutIntensity) {
  const std::string ref = wd_.path("ref.ply"), cur = wd_.path("cur.bin");
  writeAsciiPly(even(), ref, false);
  writeKittiBin(test::expressIn(odd(), poseFromXYZYPR(1.0, -0.5, 0, 5 * kDeg, 0, 0)), cur);
  expectPose(expectJson({ref, cur}), 1.0, -0.5, 0.0, 5.0, 0.0, 0.0);
}

TEST_F(DloRegister, TruncatedPlyIsNamed) {
  const std::string ply = wd_.path("truncated.ply");
  std::ofstream(ply) << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                        "property float y\nproperty float z\nend_header\n1 2 3\n4 5\n";
  expectError({ply, ply}, ply);
}

TEST_F(DloRegister, RawlogAgainstItselfIsIdentity) {
  const std::string rawlog = test::sharedData("test_velodyne_VLP16.rawlog");
  expectPose(expectJson({rawlog, rawlog, "--dof", "6"}), 0, 0, 0, 0, 0, 0);
}

TEST_F(DloRegister, HelpPrintsUsage) {
  const RunResult r = runRegister({"--help"}, wd_);
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("Usage: dlo-register [OPTIONS] REF CUR"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("RADIANS"), std::string::npos) << r.out;
}

TEST_F(DloRegister, MissingFileIsNamed) {
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  expectError({ref, wd_.path("missing.bin")}, wd_.path("missing.bin"));
}

TEST_F(DloRegister, UnknownExtensionIsNamed) {
  const std::string xyz = wd_.path("scan.xyz");
  std::ofstream(xyz) << "1 2 3\n";
  expectError({xyz, xyz}, xyz);
}

TEST_F(DloRegister, EmptyScanIsNamed) {
  const std::string empty = wd_.path("empty.bin");
  std::ofstream(empty, std::ios::binary).close();
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  expectError({ref, empty}, empty);
}

TEST_F(DloRegister, KittiSizeNotMultipleOf16IsNamed) {
  const std::string odd_size = wd_.path("odd.bin");
  std::ofstream(odd_size, std::ios::binary) << std::string(20, '\0');
  expectError({odd_size, odd_size}, odd_size);
}

TEST_F(DloRegister, BadDofIsAUsageError) {
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  expectError({ref, cur, "--dof", "4"}, "--dof", 2);
}

TEST_F(DloRegister, BadInitIsAUsageError) {
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  expectError({ref, cur, "--init", "1 2 3"}, "--init", 2);
  expectError({ref, cur, "--init", "1 2 3 4 5 x"}, "--init", 2);
}

TEST_F(DloRegister, MissingPositionalArgumentIsAUsageError) {
  expectError({}, "REF and CUR", 2);
  expectError({"a.bin", "b.bin", "--frobnicate"}, "--frobnicate", 2);
}

TEST_F(DloRegister, BadConfigValueNamesTheKeyAndFile) {
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  const std::string config = wd_.path("bad.ini");
  std::ofstream(config) << "[grid]\nresolution = 0\n";
  expectError({ref, cur, "--config", config}, "grid.resolution");
  expectError({ref, cur, "--config", config}, config);
}

TEST_F(DloRegister, UnknownConfigKeyOrMissingConfigFileIsNamed) {
  const auto [ref, cur] = writePair(Eigen::Isometry3d::Identity());
  const std::string config = wd_.path("typo.ini");
  std::ofstream(config) << "[solver]\nmax_iteration = 3\n";
  expectError({ref, cur, "--config", config}, "solver.max_iteration");
  expectError({ref, cur, "--config", wd_.path("none.ini")}, wd_.path("none.ini"));
  expectError({ref, cur, "--set", "solver.bogus=1"}, "solver.bogus");
  expectError({ref, cur, "--set", "solver.dof=abc"}, "solver.dof");
}

}  // namespace
}  // namespace dlo
