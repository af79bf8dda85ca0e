// Sweeps: determinism, noise, dropouts and motion distortion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"
#include "sim_test_worlds.h"

using namespace dlo::sim;
using Eigen::Vector3d;

namespace {

Route testRoute() {
  return Route::roundedRectangle({0, 0}, {60, 40}, 10.0);
}

SweepSimulatorParams params(SensorType type, bool noise, uint32_t seed = 1, int threads = 2) {
  SweepSimulatorParams p;
  p.model = makeLidarModel(type);
  p.noise.enabled = noise;
  p.seed = seed;
  p.threads = threads;
  return p;
}

}  // namespace

TEST(ProceduralWorld, SameSeedSameWorldOtherSeedOtherWorld) {
  const auto a = ProceduralWorld::generate(5), b = ProceduralWorld::generate(5);
  const auto c = ProceduralWorld::generate(6);
  const auto& pa = a.objects().primitives();
  const auto& pb = b.objects().primitives();
  ASSERT_EQ(pa.size(), pb.size());
  for (size_t k = 0; k < pa.size(); ++k) {
    EXPECT_EQ(pa[k].centre, pb[k].centre);
    EXPECT_EQ(pa[k].half, pb[k].half);
  }
  EXPECT_EQ(a.terrain().heightAt(12.3, 45.6), b.terrain().heightAt(12.3, 45.6));
  const auto& pc = c.objects().primitives();
  bool differs = pc.size() != pa.size() ||
                 a.terrain().heightAt(12.3, 45.6) != c.terrain().heightAt(12.3, 45.6);
  for (size_t k = 0; !differs && k < pa.size(); ++k) differs = pa[k].centre != pc[k].centre;
  EXPECT_TRUE(differs);
  // A town, not a handful of boxes.
  EXPECT_GT(pa.size(), 500u);
}

TEST(SweepSimulator, SameSeedGivesIdenticalSweepsWhateverTheThreadCount) {
  const auto world = ProceduralWorld::generate(3);
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  const SweepSimulator one(world, traj, params(SensorType::VLP16, true, 9, 1));
  const SweepSimulator two(world, traj, params(SensorType::VLP16, true, 9, 2));
  const SweepSimulator other(world, traj, params(SensorType::VLP16, true, 10, 2));
  const Sweep a = one.simulate(4), b = two.simulate(4), c = other.simulate(4);
  EXPECT_EQ(a.referenceTimeNs, b.referenceTimeNs);
  EXPECT_EQ(a.range, b.range);
  EXPECT_EQ(a.intensity, b.intensity);
  EXPECT_NE(a.range, c.range);  // Other noise.
}

TEST(SweepSimulator, SweepsAreOneRevolutionOfWholePackets) {
  const auto world = test::worldWith({});
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  for (SensorType t : {SensorType::VLP16, SensorType::HDL64}) {
    const SweepSimulator sim(world, traj, params(t, false));
    const Sweep s0 = sim.simulate(0), s1 = sim.simulate(1);
    EXPECT_EQ(s0.referenceTimeNs, 0);
    EXPECT_EQ(s0.firings % sim.model().firingsPerPacket, 0);
    // Consecutive sweeps tile time without gaps or overlaps.
    EXPECT_EQ(s0.firstFiring + s0.firings, s1.firstFiring);
    const double span = static_cast<double>(s0.firings) * sim.model().firingPeriodNs;
    EXPECT_NEAR(span, 1e8, sim.model().packetPeriodNs());
  }
}

TEST(SweepSimulator, OusterSweepsAreExactly1024ColumnsFromTheStartOfTheirRevolution) {
  const auto world = test::worldWith({});
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  const SweepSimulator sim(world, traj, params(SensorType::OS64, false));
  for (int64_t frame : {0, 1, 37}) {
    const Sweep s = sim.simulate(frame);
    EXPECT_EQ(s.firings, 1024) << frame;
    EXPECT_EQ(s.lasers, 64) << frame;
    EXPECT_EQ(s.firstFiring, 1024 * frame) << frame;
    EXPECT_EQ(s.referenceTimeNs, frame * sim.revolutionNs()) << frame;
    EXPECT_EQ(sim.azimuthDeg(s.referenceTimeNs), 0.0) << frame;
  }
}

TEST(SweepSimulator, OusterSweepOnFlatGroundReturnsEveryDownwardBeamThatReachesIt) {
  // Flat ground, no noise, the sensor level 1.8 m above it: a beam at elevation e < 0 hits the
  // ground at range 1.8 / sin(-e), in every column, if that is within the sensor's range.
  const auto world = test::worldWith({});
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  for (SensorType type : {SensorType::OS64, SensorType::OS128}) {
    const SweepSimulator sim(world, traj, params(type, false));
    const LidarModel& m = sim.model();
    int reaching = 0;
    for (double e : m.elevationDeg) {
      const double range = e < 0.0 ? 1.8 / std::sin(-e * M_PI / 180.0) : 1e9;
      reaching += range >= m.minRange && range <= m.maxRange;
    }
    EXPECT_EQ(reaching, type == SensorType::OS64 ? 31 : 62) << m.name;
    const Sweep s = sim.simulate(0);
    const auto returns =
        std::count_if(s.range.begin(), s.range.end(), [](float r) { return r > 0; });
    EXPECT_EQ(returns, 1024 * reaching) << m.name;
  }
}

TEST(SweepSimulator, SweepStartsAtTheGivenAzimuthAndTurnsInTheSpinDirection) {
  const auto world = test::worldWith({});
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  // Azimuth of the beam of laser 0 at firing f, degrees counter-clockwise from +x.
  const auto azimuth = [](const SweepSimulator& sim, const Sweep& s, int f) {
    const Vector3d d = sim.beamDirection(0, sim.azimuthDeg(sim.pointTimeNs(s, f, 0)));
    return std::atan2(d.y(), d.x()) * 180.0 / M_PI;
  };
  struct Case {
    double start;
    int spin;
  };
  for (const Case c : {Case{0.0, -1}, Case{90.0, -1}, Case{90.0, 1}, Case{-135.0, 1}}) {
    // Sweeps of whole revolutions: their first firing is at the start exactly.
    SweepSimulatorParams p = params(SensorType::OS64, false);
    p.model.sweepStartDeg = c.start;
    p.model.spinDirection = c.spin;
    const SweepSimulator sim(world, traj, p);
    const double step = p.model.azimuthResolutionDeg();
    for (int64_t frame : {0, 3}) {
      const Sweep s = sim.simulate(frame);
      SCOPED_TRACE(testing::Message()
                   << "start " << c.start << " spin " << c.spin << " frame " << frame);
      EXPECT_NEAR(std::remainder(azimuth(sim, s, 0) - c.start, 360.0), 0.0, 1e-9);
      EXPECT_NEAR(std::remainder(azimuth(sim, s, 100) - c.start, 360.0), c.spin * 100 * step, 1e-9);
      EXPECT_NEAR(std::remainder(azimuth(sim, s, s.firings / 3) - c.start, 360.0),
                  c.spin * (s.firings / 3) * step, 1e-9);
    }
  }
}

TEST(SweepSimulator, NoiseHasTwoCentimetreSigmaAndDropsAFewPercent) {
  const auto world = ProceduralWorld::generate(2);
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  const Sweep exact = SweepSimulator(world, traj, params(SensorType::VLP16, false)).simulate(0);
  const Sweep noisy = SweepSimulator(world, traj, params(SensorType::VLP16, true)).simulate(0);
  size_t hits = 0, kept = 0;
  double sum2 = 0;
  for (size_t k = 0; k < exact.range.size(); ++k) {
    if (exact.range[k] <= 0) continue;
    ++hits;
    if (noisy.range[k] <= 0) continue;
    ++kept;
    sum2 += std::pow(noisy.range[k] - exact.range[k], 2);
  }
  ASSERT_GT(hits, 10000u);
  const double dropped = 1.0 - static_cast<double>(kept) / hits;
  EXPECT_GT(dropped, 0.02);
  EXPECT_LT(dropped, 0.04);
  EXPECT_NEAR(std::sqrt(sum2 / kept), 0.02, 0.002);
}

TEST(SweepSimulator, SeesTheTownAndNothingInTheSky) {
  const auto world = ProceduralWorld::generate(1);
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  const SweepSimulator sim(world, traj, params(SensorType::HDL64, false));
  const Sweep s = sim.simulate(0);
  std::map<SurfaceClass, int> count;
  for (auto c : s.surface) count[c]++;
  for (SurfaceClass c :
       {SurfaceClass::Road, SurfaceClass::Sidewalk, SurfaceClass::Building, SurfaceClass::Trunk,
        SurfaceClass::Foliage, SurfaceClass::Car, SurfaceClass::Pole}) {
    EXPECT_GT(count[c], 50) << "surface class " << static_cast<int>(c);
  }
  // Upward lasers see the sky between buildings: some rays return nothing.
  EXPECT_GT(count[SurfaceClass::None], 1000);
  EXPECT_GT(s.firings * s.lasers, 120000);
}

TEST(SweepSimulator, PointsTakenAtTheirOwnTimeLandOnAStaticWall) {
  // A wall 10 m ahead of the start, across the road; the vehicle drives at ~10 m/s towards it.
  const auto world = test::worldWith({makePrimitive(Shape::Box, SurfaceClass::Building,
                                                    Vector3d(40.5, 0, 5), Vector3d(0.5, 30, 5))});
  const Route route = testRoute();
  const VehicleTrajectory traj(route, world.terrain());
  for (SensorType type : {SensorType::VLP16, SensorType::HDL32}) {
    const SweepSimulator sim(world, traj, params(type, false));
    const Sweep s = sim.simulate(0);
    const Eigen::Isometry3d atReference = sim.sensorPoseAt(s.referenceTimeNs);
    double worstOwnTime = 0, worstReference = 0;
    int onWall = 0;
    for (int f = 0; f < s.firings; ++f) {
      for (int l = 0; l < s.lasers; ++l) {
        if (s.surface[s.index(f, l)] != SurfaceClass::Building) continue;
        const Vector3d p = sim.sensorPoint(s, f, l);
        const Vector3d own = sim.sensorPoseAt(sim.pointTimeNs(s, f, l)) * p;
        worstOwnTime = std::max(worstOwnTime, std::abs(own.x() - 40.0));
        worstReference = std::max(worstReference, std::abs((atReference * p).x() - 40.0));
        ++onWall;
      }
    }
    ASSERT_GT(onWall, 1000) << sim.model().name;
    EXPECT_LT(worstOwnTime, 1e-3) << sim.model().name;
    // Uncorrected, the end of the sweep is ~0.1 s x 10 m/s off: the distortion is there.
    EXPECT_GT(worstReference, 0.5) << sim.model().name;
  }
}
