// The odometry on steep hills: a simulated HDL-64 drive (dlo-simulate's --hills 0.2 town, noise,
// dropouts and motion distortion on) over a crest and into a dip. With levelling (the default)
// the height and pitch follow the truth; the paper's planar 3-DoF odometry (levelling = 0) keeps
// the first scan's plane and misses them by metres and degrees. DLO_TEST_VERBOSE=1 prints every
// scan.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "dlo/core/units.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"
#include "dlo/slam/lidar_odometry.h"

namespace dlo {
namespace {

constexpr int kScans = 30;

/// Largest errors of an odometry against the truth over a drive.
struct Errors {
  double z = 0.0;      ///< metres
  double pitch = 0.0;  ///< radians
  double roll = 0.0;   ///< radians
  double xy = 0.0;     ///< metres
};

Eigen::Vector3d ypr(const Eigen::Isometry3d& T) {
  // Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Matrix3d& R = T.linear();
  return {std::atan2(R(1, 0), R(0, 0)), std::asin(-std::clamp(R(2, 0), -1.0, 1.0)),
          std::atan2(R(2, 1), R(2, 2))};
}

void update(Errors& e, const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  e.z = std::max(e.z, std::abs(estimate.translation().z() - truth.translation().z()));
  e.xy = std::max(e.xy, (estimate.translation() - truth.translation()).head<2>().norm());
  const Eigen::Vector3d a = ypr(estimate), b = ypr(truth);
  e.pitch = std::max(e.pitch, std::abs(a(1) - b(1)));
  e.roll = std::max(e.roll, std::abs(a(2) - b(2)));
}

TEST(SlamOnSlopes, LevellingFollowsHeightAndPitchOverACrestWherePlanarOdometryCannot) {
  sim::WorldParams town;
  town.maxGrade = 0.2;
  const sim::ProceduralWorld world = sim::ProceduralWorld::generate(1, town);
  const sim::Route route = sim::Route::roundedRectangle(town.loopMin, town.loopMax, 10.0);
  const sim::VehicleTrajectory trajectory(route, world.terrain());
  sim::SweepSimulatorParams sp;
  sp.model = sim::makeLidarModel(sim::SensorType::HDL64);
  sp.seed = 1;
  const sim::SweepSimulator simulator(world, trajectory, sp);
  const Eigen::Isometry3d mount = trajectory.sensorMount();

  SlamParams levelled;  // the defaults
  ASSERT_TRUE(levelled.odometry.levelling);
  SlamParams planar = levelled;
  planar.odometry.levelling = false;
  LidarOdometry with(levelled), without(planar);
  Errors e_with, e_without;
  double climb = 0.0, turn = 0.0;
  const bool verbose = std::getenv("DLO_TEST_VERBOSE") != nullptr;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  for (int k = 0; k < kScans; ++k) {
    const sim::Sweep sweep = simulator.simulate(k);
    const double time = static_cast<double>(sweep.referenceTimeNs) * 1e-9;
    PointCloud points;
    std::vector<float> times;
    for (int f = 0; f < sweep.firings; ++f) {
      for (int l = 0; l < sweep.lasers; ++l) {
        if (sweep.range[sweep.index(f, l)] < 2.0f) continue;
        points.push_back((mount * simulator.sensorPoint(sweep, f, l)).cast<float>());
        const int64_t ns = simulator.pointTimeNs(sweep, f, l) - sweep.referenceTimeNs;
        times.push_back(static_cast<float>(static_cast<double>(ns) * 1e-9));
      }
    }
    if (k == 0) origin = trajectory.vehiclePose(time);
    const Eigen::Isometry3d truth = origin.inverse() * trajectory.vehiclePose(time);
    const OdometryStep a = with.process(time, points, times);
    const OdometryStep b = without.process(time, points, times);
    update(e_with, a.pose, truth);
    update(e_without, b.pose, truth);
    climb = std::max(climb, std::abs(truth.translation().z()));
    turn = std::max(turn, std::abs(ypr(truth)(1)));
    if (verbose) {
      std::printf(
          "scan %2d truth z %6.3f pitch %6.2f | levelled z %6.3f pitch %6.2f (%d) | "
          "planar z %6.3f pitch %6.2f\n",
          k, truth.translation().z(), ypr(truth)(1) / kDeg, a.pose.translation().z(),
          ypr(a.pose)(1) / kDeg, a.levelled ? 1 : 0, b.pose.translation().z(),
          ypr(b.pose)(1) / kDeg);
    }
  }
  std::printf(
      "truth: climb %.2f m, pitch change %.2f deg; levelled: z %.3f m, pitch %.2f deg, "
      "roll %.2f deg, xy %.3f m; planar: z %.3f m, pitch %.2f deg, roll %.2f deg, "
      "xy %.3f m\n",
      climb, turn / kDeg, e_with.z, e_with.pitch / kDeg, e_with.roll / kDeg, e_with.xy, e_without.z,
      e_without.pitch / kDeg, e_without.roll / kDeg, e_without.xy);
  // The drive does climb and tilt, and the planar odometry misses it.
  ASSERT_GT(climb, 1.0);
  ASSERT_GT(turn, 4.0 * kDeg);
  EXPECT_GT(e_without.z, 1.0);
  EXPECT_GT(e_without.pitch, 4.0 * kDeg);
  EXPECT_LT(e_with.z, 0.08);
  EXPECT_LT(e_with.pitch, 0.4 * kDeg);
  EXPECT_LT(e_with.roll, 0.4 * kDeg);
  EXPECT_LT(e_with.xy, e_without.xy);
}

}  // namespace
}  // namespace dlo
