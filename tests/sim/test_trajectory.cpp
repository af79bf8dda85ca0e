// Ground truth of the vehicle: continuity, limits, the closed loop and attitude on the ground.
#include <gtest/gtest.h>

#include <cmath>

#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/vehicle_trajectory.h"

using namespace dlo::sim;

namespace {

/// The world and route dlo-simulate uses, built once for all tests here.
struct Scenario {
  ProceduralWorld world = ProceduralWorld::generate(1);
  WorldParams layout;
  Route route = Route::roundedRectangle(layout.loopMin, layout.loopMax, 10.0);
  VehicleTrajectory trajectory{route, world.terrain()};
};

const Scenario& scenario() {
  static const Scenario s;
  return s;
}

double yawOf(const Eigen::Isometry3d& p) {
  return std::atan2(p.linear()(1, 0), p.linear()(0, 0));
}

}  // namespace

TEST(VehicleTrajectory, PosesAreContinuousWithCarLikeSpeedAndYawRate) {
  const auto& s = scenario();
  const double dt = 0.01;
  const double end = 1.5 * s.route.lapDuration();
  Eigen::Isometry3d prev = s.trajectory.vehiclePose(0.0);
  double minSpeed = 1e9, maxSpeed = 0, maxYawRate = 0, maxAccel = 0, prevSpeed = -1;
  for (double t = dt; t < end; t += dt) {
    const Eigen::Isometry3d cur = s.trajectory.vehiclePose(t);
    const double speed = (cur.translation() - prev.translation()).norm() / dt;
    const double yawRate = std::remainder(yawOf(cur) - yawOf(prev), 2 * M_PI) / dt;
    minSpeed = std::min(minSpeed, speed);
    maxSpeed = std::max(maxSpeed, speed);
    maxYawRate = std::max(maxYawRate, std::abs(yawRate));
    if (prevSpeed >= 0) maxAccel = std::max(maxAccel, std::abs(speed - prevSpeed) / dt);
    prevSpeed = speed;
    prev = cur;
  }
  EXPECT_GT(minSpeed, 4.5);
  EXPECT_LT(maxSpeed, 10.5);
  EXPECT_LT(maxYawRate, 0.7);  // 5.5 m/s on a 10 m radius.
  EXPECT_LT(maxAccel, 2.5);    // No jumps in speed (the profile allows 2 m/s^2).
}

TEST(VehicleTrajectory, RouteClosesTheLoopAndThreeHundredFramesRevisitIt) {
  const auto& s = scenario();
  const Eigen::Isometry3d start = s.trajectory.vehiclePose(0.0);
  const Eigen::Isometry3d lap = s.trajectory.vehiclePose(s.route.lapDuration());
  EXPECT_LT((lap.translation() - start.translation()).norm(), 0.01);
  EXPECT_NEAR(std::remainder(yawOf(lap) - yawOf(start), 2 * M_PI), 0.0, 1e-6);
  // Half way, the vehicle is on the far side of the 60 x 40 m block.
  const Eigen::Isometry3d half = s.trajectory.vehiclePose(0.5 * s.route.lapDuration());
  EXPECT_GT((half.translation() - start.translation()).head<2>().norm(), 30.0);
  // 300 frames at 10 Hz: one lap and then some of the same street again.
  EXPECT_LT(s.route.lapDuration(), 27.0);
  EXPECT_GT(s.route.lapLength(), 150.0);
}

TEST(VehicleTrajectory, AttitudeFollowsTheGroundAndTheSensorRidesAt1p8m) {
  const auto& s = scenario();
  double maxTilt = 0;
  for (double t = 0; t < s.route.lapDuration(); t += 0.5) {
    const Eigen::Isometry3d pose = s.trajectory.vehiclePose(t);
    const Eigen::Vector3d p = pose.translation();
    const Eigen::Vector3d up = pose.linear().col(2);
    const Eigen::Vector3d normal = s.world.terrain().normalAt(p.x(), p.y());
    EXPECT_LT(std::acos(std::min(1.0, up.dot(normal))) * 180.0 / M_PI, 0.5) << "t=" << t;
    maxTilt = std::max(maxTilt, std::acos(up.z()) * 180.0 / M_PI);
    EXPECT_NEAR(p.z(), s.world.terrain().heightAt(p.x(), p.y()), 0.02) << "t=" << t;
    const Eigen::Vector3d sensor = (pose * s.trajectory.sensorMount()).translation();
    const double height = sensor.z() - s.world.terrain().heightAt(sensor.x(), sensor.y());
    EXPECT_GT(height, 1.7);
    EXPECT_LT(height, 1.9);
  }
  // The hills are felt: a tilt of some tenths of a degree at least, but gentle.
  EXPECT_GT(maxTilt, 0.3);
  EXPECT_LT(maxTilt, 6.0);
}

TEST(VehicleTrajectory, VehicleStaysOnTheRoad) {
  const auto& s = scenario();
  for (double t = 0; t < s.route.lapDuration(); t += 0.25) {
    const Eigen::Vector3d p = s.trajectory.vehiclePose(t).translation();
    EXPECT_EQ(s.world.terrain().surfaceAt(p.x(), p.y()), SurfaceClass::Road) << "t=" << t;
    EXPECT_LT(s.world.terrain().roadDistance(p.x(), p.y()), 5.0 - 1.0) << "t=" << t;
  }
}
