// Sensor profiles: the files of config/sensors/ are the profiles applied, the layering of a run's
// configuration, the choice from the evidence, and the rings of real and simulated sweeps.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "../test_data.h"
#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"
#include "dlo/slam/sensor_profile.h"
#include "dlo/slam/slam_config.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SensorProfiles, TheBuiltInProfilesAreTheFilesOfConfigSensors) {
  const fs::path dir = fs::path(DLO_SOURCE_DIR) / "config" / "sensors";
  size_t files = 0;
  for (const fs::directory_entry& f : fs::directory_iterator(dir)) {
    if (f.path().extension() == ".ini") ++files;
  }
  ASSERT_EQ(sensorProfiles().size(), files);
  for (const SensorProfile& p : sensorProfiles()) {
    const fs::path file = dir / (p.name + ".ini");
    EXPECT_EQ(p.ini, readText(file)) << file;
    // The file and the built-in profile give the same parameters.
    EXPECT_EQ(slamParamsToIni(resolveSlamParams(file.string(), {})),
              slamParamsToIni(resolveSlamParams(p.name, {})));
  }
  // The dense profile is the built-in defaults; the sparse one is not.
  EXPECT_EQ(slamParamsToIni(resolveSlamParams("dense", {})), slamParamsToIni(SlamParams()));
  EXPECT_NE(slamParamsToIni(resolveSlamParams("sparse", {})), slamParamsToIni(SlamParams()));
}

TEST(SensorProfiles, ConfigFileAndOverridesApplyOnTopOfTheProfile) {
  const fs::path ini = fs::temp_directory_path() / ("dlo_profile_" + std::to_string(::getpid()));
  std::ofstream(ini) << "[grid]\nresolution = 0.3\n";
  const SlamParams p = resolveSlamParams("sparse", {ini.string(), {"grid.cols=100"}});
  fs::remove(ini);
  EXPECT_DOUBLE_EQ(p.registration.grid.resolution, 0.3);  // the file
  EXPECT_EQ(p.registration.grid.cols, 100);               // the override
  EXPECT_EQ(p.registration.grid.rows, 400);               // the profile
  EXPECT_EQ(p.odometry.reference, Reference::kScanMap);   // the profile
}

TEST(SensorProfiles, AnUnknownProfileOrAMissingFileIsNamed) {
  try {
    resolveSlamParams("medium", {});
    ADD_FAILURE() << "accepted profile 'medium'";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'medium'"), std::string::npos) << m;
    EXPECT_NE(m.find("dense, sparse"), std::string::npos) << m;
  }
  try {
    resolveSlamParams("/nonexistent/profile.ini", {});
    ADD_FAILURE() << "accepted a missing profile file";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/profile.ini"), std::string::npos)
        << e.what();
  }
}

TEST(SensorProfiles, TheInputsBeamCountComesFirstThenTheRingsThenThePoints) {
  SensorEvidence e;
  e.points = 120000;
  e.rings.points = 100000;
  e.rings.rings = 16;
  e.rings.on_rings = 0.95;
  e.rings.coverage = 0.1;
  e.beams = 64;  // the input names a 64-beam sensor: it wins over the rings
  EXPECT_EQ(chooseSensorProfile(e).name, "dense");
  EXPECT_NE(chooseSensorProfile(e).reason.find("64 beams"), std::string::npos);
  e.beams = 0;  // the rings then decide
  EXPECT_EQ(chooseSensorProfile(e).name, "sparse");
  EXPECT_NE(chooseSensorProfile(e).reason.find("16 rings"), std::string::npos);
  e.rings.on_rings = 0.3;  // no clear rings: the point count
  EXPECT_EQ(chooseSensorProfile(e).name, "dense");
  EXPECT_NE(chooseSensorProfile(e).reason.find("120000 points"), std::string::npos);
  e.points = 30000;
  EXPECT_EQ(chooseSensorProfile(e).name, "sparse");
}

// The real HDL-64's lasers have origins of their own, centimetres apart: seen from the sensor's
// origin their elevations blur into each other (no gaps between rings), so the rings are not
// counted and its 120,000 points pick the dense profile.
TEST(RingCount, TheRealKittiSweepShowsNoClearRingsAndIsDenseByItsPoints) {
  const PointCloud points = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
  const RingEstimate r = estimateRings(points);
  EXPECT_FALSE(r.reliable());
  EXPECT_GT(r.coverage, 0.5);
  const SensorProfileChoice choice = chooseSensorProfile({0, r, points.size()});
  EXPECT_EQ(choice.name, "dense");
  EXPECT_NE(choice.reason.find("points"), std::string::npos) << choice.reason;
}

/// One simulated sweep of `type` in a town, in the vehicle frame (the sensor 1.7 m or so above
/// its origin), and the sensor's pose on the vehicle.
PointCloud simulatedSweep(sim::SensorType type, Eigen::Isometry3d& sensor_pose) {
  static const sim::ProceduralWorld world = sim::ProceduralWorld::generate(3);
  const sim::Route route = sim::Route::roundedRectangle({0, 0}, {60, 40}, 10.0);
  const sim::VehicleTrajectory trajectory(route, world.terrain());
  sim::SweepSimulatorParams params;
  params.model = sim::makeLidarModel(type);
  const sim::SweepSimulator simulator(world, trajectory, params);
  const sim::Sweep sweep = simulator.simulate(3);
  sensor_pose = Eigen::Isometry3d::Identity();
  sensor_pose.translation() = trajectory.geometry().sensorPosition;
  PointCloud points;
  for (int f = 0; f < sweep.firings; ++f) {
    for (int l = 0; l < sweep.lasers; ++l) {
      if (sweep.range[sweep.index(f, l)] <= 0.0f) continue;
      points.push_back((sensor_pose * simulator.sensorPoint(sweep, f, l)).cast<float>());
    }
  }
  return points;
}

TEST(RingCount, SimulatedSweepsShowTheirSensorsRingsSeenFromTheSensor) {
  for (const auto& [type, beams] :
       {std::pair{sim::SensorType::VLP16, 16}, std::pair{sim::SensorType::HDL32, 32},
        std::pair{sim::SensorType::HDL64, 64}}) {
    Eigen::Isometry3d sensor_pose;
    const PointCloud points = simulatedSweep(type, sensor_pose);
    const SensorEvidence e = sensorEvidence(points, 0, sensor_pose);
    std::printf("%d beams: %d rings, %.3f deg apart, %.3f on rings, %.3f covered\n", beams,
                e.rings.rings, e.rings.spacing_deg, e.rings.on_rings, e.rings.coverage);
    EXPECT_TRUE(e.rings.reliable()) << beams;
    EXPECT_GE(e.rings.rings, beams * 7 / 8) << beams;
    EXPECT_LE(e.rings.rings, beams) << beams;
    EXPECT_EQ(chooseSensorProfile(e).name, beams < kSparseRings ? "sparse" : "dense");
    // Seen from the vehicle frame's origin, metres below the sensor, the rings blur.
    EXPECT_FALSE(estimateRings(points).reliable() && estimateRings(points).rings == e.rings.rings)
        << beams;
  }
}

TEST(VisibilityCeiling, IsWhatTheSensorSeesFromEveryRangeOfTheGrid) {
  // Upper beams: HDL-64 +2 deg, HDL-32 +10.67 deg, VLP-16 +15 deg.
  for (const auto& [type, top] :
       {std::pair{sim::SensorType::VLP16, 15.0}, std::pair{sim::SensorType::HDL32, 10.67},
        std::pair{sim::SensorType::HDL64, 2.0}}) {
    Eigen::Isometry3d sensor_pose;
    const PointCloud points = simulatedSweep(type, sensor_pose);
    const SensorEvidence e = sensorEvidence(points, 0, sensor_pose);
    EXPECT_NEAR(e.top_elevation_deg, top, 0.3) << top;
    EXPECT_DOUBLE_EQ(e.sensor_height, sensor_pose.translation().z());
    const std::string profile = chooseSensorProfile(e).name;
    SlamParams p = resolveSlamParams(profile, {});
    // Off in the sparse profile.
    EXPECT_EQ(p.odometry.visibility_ceiling, profile == "dense") << top;
    p.odometry.visibility_ceiling = true;
    const VisibilityCeiling c = applyVisibilityCeiling(p, e);
    // Every beam that looks up sees a wall up to the sensor's own height from any range: the
    // grid keeps that and the band above it, which the HDL-64's +2 deg beam reaches at the
    // grid's edge (20 m): 2.5 m above the ground for these sensors 1.8 m up.
    const double half_width = 0.5 * p.registration.grid.cols * p.registration.grid.resolution;
    EXPECT_TRUE(c.applied) << top;
    EXPECT_NEAR(c.max_z,
                e.sensor_height + std::min(p.odometry.ceiling_above_sensor,
                                           half_width * std::tan(e.top_elevation_deg * M_PI / 180)),
                1e-9)
        << top;
    EXPECT_NEAR(c.max_z, 2.5, 0.05) << top;
    EXPECT_DOUBLE_EQ(c.max_z, p.registration.grid.max_z);
  }
  {
    // A sensor tilted down, whose highest beam looks 1 deg below the horizontal, sees less at the
    // grid's edge than at its foot: the ceiling is what it sees there.
    SensorEvidence down;
    down.sensor_height = 1.8;
    down.top_elevation_deg = -1.0;
    SlamParams p = resolveSlamParams("dense", {});
    const double half_width = 0.5 * p.registration.grid.cols * p.registration.grid.resolution;
    const VisibilityCeiling c = applyVisibilityCeiling(p, down);
    EXPECT_TRUE(c.applied);
    EXPECT_NEAR(c.max_z, 1.8 - half_width * std::tan(M_PI / 180), 1e-9);
    // The band is the user's: 0.5 m keeps 2.3 m for a sensor that looks up.
    SlamParams wide = resolveSlamParams("dense", {});
    wide.odometry.ceiling_above_sensor = 0.5;
    SensorEvidence up = down;
    up.top_elevation_deg = 15.0;
    EXPECT_NEAR(applyVisibilityCeiling(wide, up).max_z, 2.3, 1e-9);
  }
  // Off, or without evidence, nothing changes.
  Eigen::Isometry3d sensor_pose;
  const SensorEvidence e =
      sensorEvidence(simulatedSweep(sim::SensorType::HDL64, sensor_pose), 0, sensor_pose);
  SlamParams off;
  off.odometry.visibility_ceiling = false;
  EXPECT_FALSE(applyVisibilityCeiling(off, e).applied);
  EXPECT_DOUBLE_EQ(off.registration.grid.max_z, SlamParams().registration.grid.max_z);
  SlamParams none;
  EXPECT_FALSE(applyVisibilityCeiling(none, SensorEvidence()).applied);
  EXPECT_DOUBLE_EQ(none.registration.grid.max_z, SlamParams().registration.grid.max_z);
  // The real HDL-64 of KITTI, in its own frame: its highest beams are about 3 deg up.
  const PointCloud real = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
  const SensorEvidence k = sensorEvidence(real, 0, Eigen::Isometry3d::Identity());
  EXPECT_GT(k.top_elevation_deg, 1.5);
  EXPECT_LT(k.top_elevation_deg, 4.0);
}

TEST(SensorConfiguration, IsTheProfileThenTheLayersThenTheCeilingAsDloSlamSetsThem) {
  Eigen::Isometry3d sensor_pose;
  const SensorEvidence vlp16 =
      sensorEvidence(simulatedSweep(sim::SensorType::VLP16, sensor_pose), 0, sensor_pose);
  const SensorEvidence hdl64 =
      sensorEvidence(simulatedSweep(sim::SensorType::HDL64, sensor_pose), 0, sensor_pose);
  // auto: the profile the evidence picks, and why; the sparse profile has no ceiling.
  const SensorConfiguration sparse = configureForSensor("auto", {}, vlp16);
  EXPECT_EQ(sparse.profile.name, "sparse");
  EXPECT_EQ(sparse.profile.reason, chooseSensorProfile(vlp16).reason);
  EXPECT_FALSE(sparse.profile.ceiling.applied);
  EXPECT_EQ(sparse.params.registration.grid.cols,
            resolveSlamParams("sparse", {}).registration.grid.cols);
  // A profile named on the command line is kept whatever the evidence says, the layers apply
  // over it, and the ceiling is read off the evidence with the layers' band.
  const SensorConfiguration dense =
      configureForSensor("dense", {"", {"odometry.ceiling_above_sensor=0.5"}}, vlp16);
  EXPECT_EQ(dense.profile.name, "dense");
  EXPECT_EQ(dense.profile.reason, "--sensor-profile");
  EXPECT_TRUE(dense.profile.ceiling.applied);
  EXPECT_NEAR(dense.params.registration.grid.max_z, vlp16.sensor_height + 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(dense.profile.ceiling.max_z, dense.params.registration.grid.max_z);
  // The same as applying the ceiling to the resolved profile by hand.
  SlamParams by_hand = resolveSlamParams("dense", {});
  applyVisibilityCeiling(by_hand, hdl64);
  EXPECT_DOUBLE_EQ(configureForSensor("auto", {}, hdl64).params.registration.grid.max_z,
                   by_hand.registration.grid.max_z);
  // A bad layer is an error, as in resolveSlamParams().
  EXPECT_THROW(configureForSensor("auto", {"", {"odometry.max_yaw_rate=-1"}}, hdl64), InputError);
}

}  // namespace
}  // namespace dlo
