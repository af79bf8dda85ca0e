// dlo-slam's parameters and command line: the shipped config, bad values, bad inputs.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "../json_file.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/mrpt/kitti_scan_source.h"
#include "dlo/slam/localizer_config.h"
#include "dlo/slam/slam_config.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

TEST(SlamConfig, TheShippedConfigFileHoldsExactlyTheDefaults) {
  const SlamParams loaded =
      loadSlamParamsFile(std::string(DLO_SOURCE_DIR) + "/config/dlo-slam.ini");
  EXPECT_EQ(slamParamsToIni(loaded), slamParamsToIni(SlamParams()));
}

/// The file `relative` of the source tree must hold exactly `expected`, the text generated
/// from the parameter tables. With DLO_UPDATE_GENERATED=1 in the environment the file is
/// rewritten instead (after a change of a table: then review the diff and commit it).
void expectGenerated(const std::string& relative, const std::string& expected) {
  const fs::path path = fs::path(DLO_SOURCE_DIR) / relative;
  if (const char* update = std::getenv("DLO_UPDATE_GENERATED");
      update && std::string(update) == "1") {
    std::ofstream(path) << expected;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << "cannot read " << path;
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_TRUE(text.str() == expected)
      << path << " differs from the text the parameter tables generate; to regenerate it, run "
      << "DLO_UPDATE_GENERATED=1 ctest -R GeneratedFromTheTables, review the diff and commit.";
}

TEST(SlamConfig, TheShippedConfigFilesAreGeneratedFromTheTables) {
  expectGenerated("config/dlo-slam.ini", slamConfigFileText());
  expectGenerated("config/dlo.ini", dloConfigFileText());
}

TEST(SlamConfig, TheParameterReferenceIsGeneratedFromTheTables) {
  expectGenerated("docs/parameters.md", parameterReferenceMarkdown());
}

TEST(SlamConfig, TheGeneratedConfigFileNamesEveryKeyWithItsDoc) {
  const std::string text = slamConfigFileText();
  for (const ParamField<SlamParams>& f : slamParamTable().fields()) {
    const bool set = text.find("\n" + f.key + " = ") != std::string::npos;
    const bool commented = text.find("\n;" + f.key + " = ") != std::string::npos;
    EXPECT_TRUE(set || commented) << f.name();
    // The doc's first words open the comment above the key.
    const std::string start = "; " + f.doc.substr(0, std::min<size_t>(20, f.doc.size()));
    EXPECT_NE(text.find(start), std::string::npos) << f.name();
  }
  // The profile's keys are commented out, the others are not.
  EXPECT_NE(text.find("\n;reference = keyframe_map\n"), std::string::npos);
  EXPECT_NE(text.find("\nlevelling = true\n"), std::string::npos);
}

TEST(SlamConfig, NamedValuesAreReadByNameAndTheOldNumbersAreRejectedWithTheName) {
  SlamParams p;
  applySlamParamOverrides(
      p, {"odometry.reference=previous", "odometry.deskew=false", "loop.enabled=false"});
  EXPECT_EQ(p.odometry.reference, Reference::kPreviousScan);
  EXPECT_FALSE(p.odometry.deskew);
  EXPECT_FALSE(p.loop.enabled);
  try {
    applySlamParamOverrides(p, {"odometry.reference=3"});
    ADD_FAILURE() << "accepted odometry.reference=3";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odometry.reference = scan_map"), std::string::npos)
        << e.what();
  }
  try {
    applySlamParamOverrides(p, {"odometry.levelling=yes"});
    ADD_FAILURE() << "accepted odometry.levelling=yes";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("false or true"), std::string::npos) << e.what();
  }
}

TEST(SlamConfig, OverridesReachEverySection) {
  SlamParams p;
  applySlamParamOverrides(
      p, {"grid.resolution=0.2", "odometry.reference=keyframe", "loop.enabled=false"});
  EXPECT_DOUBLE_EQ(p.registration.grid.resolution, 0.2);
  EXPECT_EQ(p.odometry.reference, Reference::kKeyframe);
  EXPECT_FALSE(p.loop.enabled);
}

TEST(SlamConfig, AnOutOfRangeValueNamesTheKeyAndTheRange) {
  SlamParams p;
  try {
    applySlamParamOverrides(p, {"odometry.local_map_scans=500"});
    FAIL() << "accepted odometry.local_map_scans=500";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odometry.local_map_scans"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("1..100"), std::string::npos) << e.what();
  }
}

TEST(SlamConfig, TheRetiredSparseKeysAreRejectedByName) {
  SlamParams p;
  try {
    applySlamParamOverrides(p, {"odometry.sparse_coarse_step=0.02"});
    ADD_FAILURE() << "accepted odometry.sparse_coarse_step";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("odometry.sparse_coarse_step"), std::string::npos)
        << e.what();
  }
}

TEST(SlamConfig, AnUnknownKeyIsRejected) {
  SlamParams p;
  EXPECT_THROW(applySlamParamOverrides(p, {"loop.radius=3"}), InputError);
}

TEST(LocalizerConfig, TheShippedFileIsGeneratedFromTheTableAndHoldsTheDefaults) {
  expectGenerated("config/dlo-localize.ini", localizerConfigFileText());
  const LocalizerParams loaded =
      resolveLocalizerParams("", std::string(DLO_SOURCE_DIR) + "/config/dlo-localize.ini", {});
  EXPECT_EQ(localizerParamsToIni(loaded), localizerParamsToIni(LocalizerParams()));
  // The profile's key is commented out, with the dense profile's value (the default).
  EXPECT_NE(localizerConfigFileText().find("\n;max_correction = 0.5\n"), std::string::npos);
  for (const ParamField<LocalizerParams>& f : localizerParamTable().fields())
    EXPECT_NE(parameterReferenceMarkdown().find("| `" + f.key + "` |"), std::string::npos) << f.key;
}

/// Writes `text` to a file of the temporary folder named after the running test.
fs::path iniFile(const std::string& text) {
  const fs::path path = fs::temp_directory_path() /
                        (std::string("dlo_localizer_config_") +
                         ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".ini");
  std::ofstream(path) << text;
  return path;
}

TEST(LocalizerConfig, TheFileThenTheOverridesOfItsSectionApply) {
  const fs::path ini =
      iniFile("[odometry]\ndeskew = false\n[localizer]\nmax_rms = 0.7\nlost_after = 5\n");
  const std::vector<std::string> sets = {"odometry.deskew=true", "localizer.lost_after=4"};
  const LocalizerParams p = resolveLocalizerParams("", ini.string(), sets);
  EXPECT_DOUBLE_EQ(p.max_rms, 0.7);
  EXPECT_EQ(p.lost_after, 4);
  EXPECT_DOUBLE_EQ(p.search_contrast, LocalizerParams().search_contrast);
  std::vector<std::string> slam, localizer;
  splitLocalizerOverrides(sets, slam, localizer);
  EXPECT_EQ(slam, std::vector<std::string>{"odometry.deskew=true"});
  EXPECT_EQ(localizer, std::vector<std::string>{"localizer.lost_after=4"});
  // dlo-slam's sections of the same file are dlo-slam's to read, and it leaves [localizer] alone.
  EXPECT_FALSE(loadSlamParamsFile(ini.string()).odometry.deskew);
}

TEST(LocalizerConfig, ABadValueOrKeyIsOneSentenceNamingTheKey) {
  const auto message = [](const std::string& file, const std::vector<std::string>& sets) {
    try {
      resolveLocalizerParams("", file, sets);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const fs::path range = iniFile("[localizer]\nmin_inliers = 2\n");
  std::string m = message(range.string(), {});
  EXPECT_NE(m.find("localizer.min_inliers"), std::string::npos) << m;
  EXPECT_NE(m.find(range.filename().string()), std::string::npos) << m;
  m = message(iniFile("[localizer]\nmax_rmss = 1\n").string(), {});
  EXPECT_NE(m.find("localizer.max_rmss"), std::string::npos) << m;
  m = message("", {"localizer.search_every=0"});
  EXPECT_NE(m.find("localizer.search_every"), std::string::npos) << m;
  m = message("", {"localizer.search_yaw_step_deg=abc"});
  EXPECT_NE(m.find("localizer.search_yaw_step_deg"), std::string::npos) << m;
}

TEST(LocalizerConfig, TheSensorProfileSetsItsKeysBeneathTheFileAndTheOverrides) {
  // The dense profile is the defaults; the sparse one believes corrections up to 0.75 m. Both
  // stop the odometry where the map localises (bridge_only, the default).
  EXPECT_EQ(localizerParamsToIni(resolveLocalizerParams("dense", "", {})),
            localizerParamsToIni(LocalizerParams()));
  EXPECT_TRUE(resolveLocalizerParams("sparse", "", {}).bridge_only);
  EXPECT_FALSE(resolveLocalizerParams("sparse", "", {"localizer.bridge_only=false"}).bridge_only);
  EXPECT_DOUBLE_EQ(LocalizerParams().max_correction, 0.5);
  EXPECT_DOUBLE_EQ(resolveLocalizerParams("sparse", "", {}).max_correction, 0.75);
  const fs::path file =
      fs::path(DLO_SOURCE_DIR) / "config" / "sensors" / "sparse.ini";  // a profile by its path
  EXPECT_DOUBLE_EQ(resolveLocalizerParams(file.string(), "", {}).max_correction, 0.75);
  EXPECT_EQ(localizerProfileKeys(), std::vector<std::string>{"localizer.max_correction"});
  EXPECT_THROW(resolveLocalizerParams("medium", "", {}), InputError);
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

const std::string kKittiCity = std::string(DLO_SHARED_DATA_DIR) + "/kitti_city_seq";

TEST(DloSlamCommandLine, ReadsAKittiFolderDirectly) {
  const fs::path out = fs::temp_directory_path() / "dlo_slam_kitti_folder_out";
  fs::remove_all(out);
  const CliRun r = dloSlam("--input " + kKittiCity + " --out " + out.string() + " --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream tum(out / "trajectory.tum");
  std::string line;
  size_t poses = 0;
  while (std::getline(tum, line)) poses += (!line.empty() && line[0] != '#') ? 1 : 0;
  EXPECT_EQ(poses, 22u);  // one per scan of the folder
  // The real HDL-64 sweeps: dense, by their point count (their rings blur, see RingCount).
  const nlohmann::json profile = test::readJsonFile(out / "report.json").at("sensor_profile");
  EXPECT_EQ(profile.at("name"), "dense");
  EXPECT_EQ(profile.at("chosen_because").get<std::string>().rfind("the first scan has", 0), 0u)
      << profile;
  fs::remove_all(out);
}

/// dlo-slam over the real sweeps with `extra` options: its keyframe count (report.json) and
/// its last position (trajectory.tum).
struct RealDriveRun {
  int keyframes = -1;
  Eigen::Vector3d end = Eigen::Vector3d::Constant(std::nan(""));
};

RealDriveRun runRealDrive(const std::string& extra) {
  const fs::path out = fs::temp_directory_path() / "dlo_slam_real_drive_out";
  fs::remove_all(out);
  const CliRun r =
      dloSlam("--input " + kKittiCity + " --out " + out.string() + " --quiet " + extra);
  EXPECT_EQ(r.status, 0) << r.err;
  RealDriveRun run;
  run.keyframes = test::readJsonFile(out / "report.json").at("keyframes").get<int>();
  std::ifstream tum(out / "trajectory.tum");
  std::string line, last;
  while (std::getline(tum, line)) {
    if (!line.empty() && line[0] != '#') last = line;
  }
  std::istringstream fields(last);
  double t = 0.0;
  fields >> t >> run.end.x() >> run.end.y() >> run.end.z();
  fs::remove_all(out);
  return run;
}

TEST(DloSlamCommandLine, KeyframesOnRealScansComeFromTheDistanceDrivenNotFromTheFit) {
  // Real city sweeps fit 0.33-0.41 m RMS even right after a keyframe: with an absolute bound on
  // the fit (odometry.keyframe_max_rms = 0.3 m, the default until it was measured off) every
  // scan but one became a keyframe. Off by default, and relative to the fits fresh keyframes
  // give when it is set, a keyframe is made every 2 m driven (17 m here), and the trajectory
  // stays within centimetres of the other.
  const RealDriveRun defaults = runRealDrive("");
  const RealDriveRun absolute = runRealDrive("--set odometry.keyframe_max_rms=0.3");
  const RealDriveRun relative =
      runRealDrive("--set odometry.keyframe_max_rms=0.3 --set odometry.keyframe_rms_ratio=1.1");
  EXPECT_GE(absolute.keyframes, 18);
  for (const RealDriveRun* r : {&defaults, &relative}) {
    EXPECT_LE(r->keyframes, 12);
    EXPECT_GE(r->keyframes, 8);  // the distance rule still holds: 17 m at one per 2 m
    EXPECT_LT((absolute.end - r->end).norm(), 0.1);
  }
  EXPECT_GT(absolute.end.x(), 15.0);  // about 17 m forward
}

TEST(DloSlamCommandLine, AnUnknownSensorProfileIsNamed) {
  const CliRun r = dloSlam("--input " + kKittiCity +
                           " --out /tmp/dlo_slam_cli_out --sensor-profile medium --quiet");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("'medium'"), std::string::npos) << r.err;
}

TEST(DloSlamCommandLine, AFolderWithoutScansIsNamed) {
  const fs::path empty = fs::temp_directory_path() / "dlo_slam_empty_kitti_folder";
  fs::create_directories(empty);
  const CliRun r = dloSlam("--input " + empty.string() + " --out /tmp/dlo_slam_cli_out");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(empty.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(".bin"), std::string::npos) << r.err;
}

TEST(KittiScanSource, StopsAtACorruptScanNamingItAndKeepsTheScansBefore) {
  const fs::path dir = fs::temp_directory_path() / "dlo_kitti_source_corrupt";
  fs::remove_all(dir);
  fs::create_directories(dir / "velodyne");
  fs::copy_file(kKittiCity + "/000000.bin.gz", dir / "velodyne" / "000000.bin.gz");
  fs::copy_file(kKittiCity + "/000001.bin.gz", dir / "velodyne" / "000001.bin.gz");
  std::ofstream(dir / "velodyne" / "000002.bin") << "not 16-byte records";
  std::ofstream(dir / "times.txt") << "0.0\n0.1\n0.2\n";
  ScanSourceOptions options;
  options.min_range = 2.0;
  KittiScanSource source(dir.string(), options);
  TimedScan scan;
  ASSERT_TRUE(source.next(scan));
  EXPECT_GT(scan.points.size(), 100000u);
  EXPECT_GT(scan.dropped_by_range, 0u);
  EXPECT_TRUE(scan.point_times.empty());
  ASSERT_TRUE(source.next(scan));
  EXPECT_DOUBLE_EQ(scan.timestampSeconds(), 0.1);
  EXPECT_FALSE(source.next(scan));
  EXPECT_EQ(source.stats().scans, 2u);
  EXPECT_NE(source.stats().error.find("000002.bin"), std::string::npos) << source.stats().error;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dlo
