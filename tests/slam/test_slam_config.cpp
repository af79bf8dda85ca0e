// dlo-slam's parameters and command line: the shipped config, bad values, bad inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "dlo/mrpt/input_error.h"
#include "dlo/slam/slam_config.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

TEST(SlamConfig, TheShippedConfigFileHoldsExactlyTheDefaults) {
  const SlamParams loaded =
      loadSlamParamsFile(std::string(DLO_SOURCE_DIR) + "/config/dlo-slam.ini");
  EXPECT_EQ(slamParamsToIni(loaded), slamParamsToIni(SlamParams()));
}

TEST(SlamConfig, OverridesReachEverySection) {
  SlamParams p;
  applySlamParamOverrides(p, {"grid.resolution=0.2", "odometry.reference=0", "loop.enabled=0"});
  EXPECT_DOUBLE_EQ(p.registration.grid.resolution, 0.2);
  EXPECT_EQ(p.odometry.reference, 0);
  EXPECT_EQ(p.loop.enabled, 0);
}

TEST(SlamConfig, AnOutOfRangeValueNamesTheKeyAndTheRange) {
  SlamParams p;
  try {
    applySlamParamOverrides(p, {"odometry.reference=5"});
    FAIL() << "accepted odometry.reference=5";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odometry.reference"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0 (frame)"), std::string::npos) << e.what();
  }
}

TEST(SlamConfig, AnUnknownKeyIsRejected) {
  SlamParams p;
  EXPECT_THROW(applySlamParamOverrides(p, {"loop.radius=3"}), InputError);
}

struct CliRun {
  int status;
  std::string err;
};

CliRun dloSlam(const std::string& args) {
  // One file per test: ctest runs tests in parallel.
  const fs::path err = fs::temp_directory_path() /
                       (std::string("dlo_slam_cli_") +
                        ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".err");
  const std::string cmd =
      std::string(DLO_SLAM_BINARY) + " " + args + " > /dev/null 2> " + err.string();
  const int raw = std::system(cmd.c_str());
  std::ifstream f(err);
  std::stringstream s;
  s << f.rdbuf();
  return CliRun{WEXITSTATUS(raw), s.str()};
}

TEST(DloSlamCommandLine, HelpExitsZero) {
  EXPECT_EQ(dloSlam("--help").status, 0);
}

TEST(DloSlamCommandLine, AMissingInputIsOneSentenceNamingTheFile) {
  const CliRun r = dloSlam("--input /nonexistent/drive.rawlog --out /tmp/dlo_slam_cli_out");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/nonexistent/drive.rawlog"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.rfind("dlo-slam: ", 0), 0u) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(DloSlamCommandLine, ABadParameterNamesTheKey) {
  const CliRun r = dloSlam("--input x.rawlog --out /tmp/dlo_slam_cli_out --set solver.dof=4");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("solver.dof"), std::string::npos) << r.err;
}

TEST(DloSlamCommandLine, AMissingRequiredOptionIsAUsageError) {
  const CliRun r = dloSlam("--out /tmp/dlo_slam_cli_out");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--input"), std::string::npos) << r.err;
}

TEST(DloSlamCommandLine, APcapNeedsAModel) {
  const CliRun r = dloSlam("--input capture.pcap --out /tmp/dlo_slam_cli_out");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--model"), std::string::npos) << r.err;
}

TEST(DloSlamCommandLine, AFileThatIsNotARawlogIsNamed) {
  const fs::path bogus = fs::temp_directory_path() / "dlo_slam_not_a_rawlog.rawlog";
  std::ofstream(bogus) << "this is not an MRPT rawlog\n";
  const CliRun r = dloSlam("--input " + bogus.string() + " --out /tmp/dlo_slam_cli_out");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(bogus.string()), std::string::npos) << r.err;
}

}  // namespace
}  // namespace dlo
