// The drive conditions dlo-simulate offers beyond the town's laps: steep hills with crests and
// dips, an open road with little structure, hard stops.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/vehicle_trajectory.h"

using namespace dlo::sim;

namespace {

/// Grade of the vehicle's forward axis: rise over run.
double gradeOf(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d x = pose.linear().col(0);
  return x.z() / x.head<2>().norm();
}

/// The town on hills of at most `maxGrade` (gentle ones for 0) and its loop.
struct HillDrive {
  explicit HillDrive(uint32_t seed, double maxGrade)
      : world(ProceduralWorld::generate(seed, params(maxGrade))) {}
  static WorldParams params(double maxGrade) {
    WorldParams p;
    p.maxGrade = maxGrade;
    return p;
  }
  ProceduralWorld world;
  WorldParams layout;
  Route route = Route::roundedRectangle(layout.loopMin, layout.loopMax, 10.0);
  VehicleTrajectory trajectory{route, world.terrain()};
};

/// Along one lap: the steepest grade, and the crests and dips (the grade turning from above
/// +threshold to below -threshold, and back).
struct GradeProfile {
  double steepest = 0.0;
  int crests = 0, dips = 0;
};

GradeProfile gradeProfile(const HillDrive& d, double threshold) {
  GradeProfile g;
  int lastSign = 0;
  for (double t = 0.0; t < d.route.lapDuration(); t += 0.02) {
    const double grade = gradeOf(d.trajectory.vehiclePose(t));
    g.steepest = std::max(g.steepest, std::abs(grade));
    const int sign = grade > threshold ? 1 : grade < -threshold ? -1 : 0;
    if (sign == 0 || sign == lastSign) continue;
    if (lastSign == 1) ++g.crests;
    if (lastSign == -1) ++g.dips;
    lastSign = sign;
  }
  return g;
}

}  // namespace

TEST(SteepHills, TheDriveClimbsAndDescendsCloseToTheBoundWithCrestsAndDips) {
  for (uint32_t seed : {1u, 2u, 3u}) {
    const HillDrive d(seed, 0.2);
    const GradeProfile g = gradeProfile(d, 0.05);
    EXPECT_LE(g.steepest, 0.2) << "seed " << seed;
    EXPECT_GE(g.steepest, 0.14) << "seed " << seed;
    EXPECT_GE(g.crests, 1) << "seed " << seed;
    EXPECT_GE(g.dips, 1) << "seed " << seed;
  }
  // The town's gentle hills, for contrast: the option is what makes the drive steep.
  EXPECT_LT(gradeProfile(HillDrive(1, 0.0), 0.05).steepest, 0.1);
  // The same seed gives the same hills.
  const HillDrive a(4, 0.15), b(4, 0.15);
  EXPECT_EQ(a.world.terrain().heightAt(31.0, 2.0), b.world.terrain().heightAt(31.0, 2.0));
  EXPECT_THROW(steepHills(0.01, TerrainParams(), 1), std::invalid_argument);
}

TEST(SteepHills, GroundTruthHeightAndAttitudeFollowTheRoad) {
  const HillDrive d(1, 0.2);
  const Terrain& ground = d.world.terrain();
  const double a = 0.5 * d.trajectory.geometry().wheelbase;
  double maxPitch = 0.0;
  for (double t = 0.0; t < d.route.lapDuration(); t += 0.1) {
    const Eigen::Isometry3d pose = d.trajectory.vehiclePose(t);
    const Eigen::Vector3d p = pose.translation();
    EXPECT_NEAR(p.z(), ground.heightAt(p.x(), p.y()), 0.03) << "t=" << t;
    // The pitch is the road's grade between the axles; the roll leaves the vehicle's up axis
    // on the ground's normal.
    const RouteState st = d.route.stateAt(t);
    const Eigen::Vector2d f(std::cos(st.heading), std::sin(st.heading));
    const Eigen::Vector2d front = st.position + a * f, rear = st.position - a * f;
    const double roadGrade =
        (ground.heightAt(front.x(), front.y()) - ground.heightAt(rear.x(), rear.y())) / (2 * a);
    EXPECT_NEAR(gradeOf(pose), roadGrade, 0.005) << "t=" << t;
    const Eigen::Vector3d normal = ground.normalAt(p.x(), p.y());
    EXPECT_LT(std::acos(std::min(1.0, pose.linear().col(2).dot(normal))) * 180 / M_PI, 0.7)
        << "t=" << t;
    maxPitch = std::max(maxPitch, std::abs(std::atan(gradeOf(pose))) * 180 / M_PI);
  }
  EXPECT_GT(maxPitch, 6.0);
}

TEST(SteepHills, ObjectsStandOnTheGround) {
  const HillDrive d(2, 0.2);
  const Terrain& ground = d.world.terrain();
  int poles = 0;
  for (const Primitive& p : d.world.objects().primitives()) {
    const double base = p.centre.z() - p.half.z();
    const double z = ground.heightAt(p.centre.x(), p.centre.y());
    if (p.surface == SurfaceClass::Pole || p.surface == SurfaceClass::Trunk) {
      EXPECT_LE(base, z);        // No gap under them...
      EXPECT_GT(base, z - 0.5);  // ...nor sunk.
      poles += p.surface == SurfaceClass::Pole;
    } else if (p.surface == SurfaceClass::Building) {
      EXPECT_LE(base, z);
      EXPECT_GT(p.centre.z() + p.half.z(), z + 3.0);
    }
  }
  EXPECT_GT(poles, 20);
}

namespace {

/// Primitives within `lateral` of the straight from (x0, y) to (x1, y), per 100 m of it.
double objectsPer100m(const ProceduralWorld& w, double x0, double x1, double y, double lateral) {
  int n = 0;
  for (const Primitive& p : w.objects().primitives())
    n += p.centre.x() >= x0 && p.centre.x() <= x1 && std::abs(p.centre.y() - y) <= lateral;
  return 100.0 * n / (x1 - x0);
}

}  // namespace

TEST(OpenRoad, HasFewObjectsBesideItAndTheCarDrivesAlongIt) {
  const OpenRoadParams params;
  const ProceduralWorld road = ProceduralWorld::generateOpenRoad(1, params);
  for (const Primitive& p : road.objects().primitives()) {
    EXPECT_TRUE(p.surface == SurfaceClass::Pole || p.surface == SurfaceClass::Trunk ||
                p.surface == SurfaceClass::Foliage)
        << static_cast<int>(p.surface);
  }
  EXPECT_TRUE(road.traffic().cars().empty());
  // Along the first straight: a pole every ~60 m and a clump of trees every ~200 m.
  const double open = objectsPer100m(road, 0.0, 500.0, 0.0, 60.0);
  EXPECT_GT(open, 1.0);
  EXPECT_LT(open, 8.0);
  const ProceduralWorld town = ProceduralWorld::generate(1);
  EXPECT_GT(objectsPer100m(town, -120.0, 180.0, 0.0, 60.0), 5.0 * open);

  // The car drives the road: 585 m straight east at the cruise speed, on the road all along.
  SpeedLimits limits;
  limits.cruise = params.cruise;
  const Route route = Route::roundedRectangle(params.loopMin, params.loopMax, 10.0, 8.0, limits);
  const VehicleTrajectory trajectory(route, road.terrain());
  for (double t = 0.0; t < 60.0; t += 0.25) {
    const Eigen::Vector3d p = trajectory.vehiclePose(t).translation();
    EXPECT_LT(road.terrain().roadDistance(p.x(), p.y()), 4.0) << "t=" << t;
    EXPECT_NEAR(p.z(), road.terrain().heightAt(p.x(), p.y()), 0.03) << "t=" << t;
  }
  const RouteState st = route.stateAt(35.0);
  EXPECT_NEAR(st.position.x(), 35.0 * params.cruise, 1e-6);
  EXPECT_NEAR(st.heading, 0.0, 1e-12);
  EXPECT_GT(route.stateAt(45.0).position.y(), 5.0);  // Round the first corner.
}

TEST(Stops, TheCarBrakesHardStandsStillForTwoSecondsAndDrivesOn) {
  const OpenRoadParams road;
  SpeedLimits limits;
  limits.cruise = road.cruise;
  const Route plain = Route::roundedRectangle(road.loopMin, road.loopMax, 10.0, 8.0, limits);
  Route route = plain;
  const StopParams stops;
  route.setStops(stops, 40.0);
  const double dt = 0.001;
  double maxDecel = 0.0, maxAccel = 0.0, still = 0.0, prevSpeed = route.stateAt(0.0).speed;
  Eigen::Vector2d stillAt = Eigen::Vector2d::Constant(1e9);
  int standstills = 0;
  std::vector<double> durations;
  for (double t = dt; t < 40.0; t += dt) {
    const RouteState st = route.stateAt(t);
    const double accel = (st.speed - prevSpeed) / dt;
    maxDecel = std::max(maxDecel, -accel);
    maxAccel = std::max(maxAccel, accel);
    if (st.speed == 0.0) {
      if (still == 0.0) {
        ++standstills;
        stillAt = st.position;
      }
      EXPECT_LT((st.position - stillAt).norm(), 1e-9) << "t=" << t;  // Really standing.
      EXPECT_EQ(st.yawRate, 0.0);
      still += dt;
    } else if (still > 0.0) {
      durations.push_back(still);
      still = 0.0;
    }
    prevSpeed = st.speed;
    if (t < stops.first) {  // Before the first stop: the route's own timing.
      EXPECT_EQ(st.position, plain.stateAt(t).position);
    }
  }
  // Braking from 15 m/s at 7 m/s^2 (2.1 s), 2 s still, 6 s back to speed: stops at 6, 18, 30 s.
  EXPECT_EQ(standstills, 3);
  for (double d : durations) EXPECT_NEAR(d, stops.wait, 2 * dt);
  EXPECT_NEAR(maxDecel, stops.braking, 0.01);
  EXPECT_NEAR(maxAccel, stops.accel, 0.01);
  EXPECT_NEAR(route.stateAt(17.0).speed, road.cruise, 1e-9);  // Back at speed between stops.
  // The same path: where the plain route is at a distance, the stopping one gets there later.
  const RouteState late = route.stateAt(20.0);
  EXPECT_LT(late.distance, plain.stateAt(20.0).distance);
  StopParams bad;
  bad.braking = 0.0;
  EXPECT_THROW(route.setStops(bad, 10.0), std::invalid_argument);
}
