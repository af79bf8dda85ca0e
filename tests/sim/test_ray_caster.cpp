// Ray casting against known shapes and known ground.
#include <gtest/gtest.h>

#include <cmath>

#include "dlo/sim/ray_caster.h"
#include "sim_test_worlds.h"

using namespace dlo::sim;
using Eigen::Vector3d;

namespace {

RayHit castOnce(const ProceduralWorld& world, const Vector3d& o, const Vector3d& d,
                double maxRange = 100.0) {
  GridScratch scratch;
  return RayCaster(world).cast(o, d.normalized(), maxRange, {}, scratch);
}

}  // namespace

TEST(RayCaster, HitsABoxFaceAtItsDistance) {
  const auto world = test::worldWith(
      {makePrimitive(Shape::Box, SurfaceClass::Building, Vector3d(10, 0, 2), Vector3d(1, 1, 2))});
  const RayHit hit = castOnce(world, Vector3d(0, 0, 1), Vector3d(1, 0, 0));
  ASSERT_TRUE(hit.valid());
  EXPECT_NEAR(hit.t, 9.0, 1e-9);
  EXPECT_EQ(hit.surface, SurfaceClass::Building);
}

TEST(RayCaster, HitsARotatedBoxOnItsCorner) {
  // A 2 x 2 box turned by 45 deg: its corner points at the ray, sqrt(2) in front of the centre.
  const auto world = test::worldWith({makePrimitive(
      Shape::Box, SurfaceClass::Car, Vector3d(10, 0, 1), Vector3d(1, 1, 1), M_PI / 4)});
  const RayHit hit = castOnce(world, Vector3d(0, 0, 1), Vector3d(1, 0, 0));
  ASSERT_TRUE(hit.valid());
  EXPECT_NEAR(hit.t, 10.0 - std::sqrt(2.0), 1e-9);
}

TEST(RayCaster, HitsCylinderEllipsoidAndGableRoofWhereExpected) {
  const auto world = test::worldWith(
      {makePrimitive(Shape::Cylinder, SurfaceClass::Pole, Vector3d(5, 0, 3), Vector3d(0.2, 0.2, 3)),
       makePrimitive(Shape::Ellipsoid, SurfaceClass::Foliage, Vector3d(0, 8, 5),
                     Vector3d(2, 3, 1.5)),
       // Ridge along x at z = 12, eaves at z = 10 and y = +-4.
       makePrimitive(Shape::GableRoof, SurfaceClass::Roof, Vector3d(-20, 0, 11),
                     Vector3d(5, 4, 1))});
  const RayHit pole = castOnce(world, Vector3d(0, 0, 1), Vector3d(1, 0, 0));
  EXPECT_NEAR(pole.t, 4.8, 1e-9);
  EXPECT_EQ(pole.surface, SurfaceClass::Pole);
  const RayHit crown = castOnce(world, Vector3d(0, 0, 5), Vector3d(0, 1, 0));
  EXPECT_NEAR(crown.t, 5.0, 1e-9);
  EXPECT_EQ(crown.surface, SurfaceClass::Foliage);
  // Straight down onto the roof 2 m from the ridge: it drops 2 m over 4 m, so z = 11 there.
  const RayHit roof = castOnce(world, Vector3d(-20, 2, 20), Vector3d(0, 0, -1));
  EXPECT_NEAR(roof.t, 20.0 - 11.0, 1e-9);
  EXPECT_EQ(roof.surface, SurfaceClass::Roof);
}

TEST(RayCaster, HitsFlatGroundAtHeightOverSineOfDepression) {
  const auto world = test::worldWith({});
  for (double deg : {-2.0, -10.0, -24.9, -60.0}) {
    const double e = deg * M_PI / 180.0;
    const RayHit hit =
        castOnce(world, Vector3d(3, -4, 1.8), Vector3d(std::cos(e), 0.3, std::sin(e)));
    ASSERT_TRUE(hit.valid()) << deg;
    const Vector3d d = Vector3d(std::cos(e), 0.3, std::sin(e)).normalized();
    EXPECT_NEAR(hit.t, 1.8 / -d.z(), 1e-3) << deg;
    EXPECT_EQ(hit.surface, SurfaceClass::Grass);
  }
}

TEST(RayCaster, RaysAboveTheHorizonOrBeyondMaxRangeReturnNothing) {
  const auto world = test::worldWith({});
  EXPECT_FALSE(castOnce(world, Vector3d(0, 0, 1.8), Vector3d(1, 0, 0.1)).valid());
  // Would hit the ground at 1.8 / sin(1 deg) = 103 m.
  const double e = -1.0 * M_PI / 180.0;
  EXPECT_FALSE(
      castOnce(world, Vector3d(0, 0, 1.8), Vector3d(std::cos(e), 0, std::sin(e)), 100.0).valid());
}

TEST(RayCaster, FindsTheKerbAsAStepAtTheRoadEdge) {
  TerrainParams ground = test::flatGround();
  ground.roads.push_back({{-100.0, 0.0}, {100.0, 0.0}});  // Along x, 5 m half width.
  const auto world = test::worldWith({}, ground);
  const Terrain& t = world.terrain();
  // The road is sunk by the kerb and crowned: 4 cm higher at its centre than at its edges.
  EXPECT_NEAR(t.heightAt(0, 0), -0.13 + 0.04, 1e-6);
  EXPECT_NEAR(t.heightAt(0, 4.99), -0.13, 1e-3);
  EXPECT_NEAR(t.heightAt(0, 5.01), 0.0, 1e-6);
  EXPECT_EQ(t.surfaceAt(0, 0), SurfaceClass::Road);
  EXPECT_EQ(t.surfaceAt(0, 6), SurfaceClass::Sidewalk);
  EXPECT_EQ(t.surfaceAt(0, 9), SurfaceClass::Grass);
  // A ray skimming the road 5 cm above its edge hits the kerb face at y = 5.
  const RayHit hit = castOnce(world, Vector3d(0.3, 0, -0.08), Vector3d(0, 1, 0));
  ASSERT_TRUE(hit.valid());
  EXPECT_NEAR(hit.t, 5.0, 0.01);
}

TEST(RayCaster, TheNearestOfGroundAndObjectsWins) {
  const auto world = test::worldWith(
      {makePrimitive(Shape::Box, SurfaceClass::Building, Vector3d(30, 0, 5), Vector3d(1, 10, 5))});
  // Down at 10 deg: the ground (10.4 m) is in front of the wall (29 m).
  const double e = -10.0 * M_PI / 180.0;
  const RayHit low = castOnce(world, Vector3d(0, 0, 1.8), Vector3d(std::cos(e), 0, std::sin(e)));
  EXPECT_EQ(low.surface, SurfaceClass::Grass);
  const RayHit level = castOnce(world, Vector3d(0, 0, 1.8), Vector3d(1, 0, 0));
  EXPECT_EQ(level.surface, SurfaceClass::Building);
  EXPECT_NEAR(level.t, 29.0, 1e-9);
}

TEST(RayCaster, MovingCarsAreHitAtTheirCurrentPlace) {
  const auto world = test::worldWith({});
  Traffic traffic({MovingCar{{-50.0, 0.0}, {1.0, 0.0}, 100.0, 10.0, 0.0}});
  std::vector<Primitive> cars;
  GridScratch scratch;
  RayCaster caster(world);
  // At t = 6 s the car's centre is at x = 10; its body spans x in [7.75, 12.25].
  traffic.primitivesAt(6.0, world.terrain(), {0.0, 0.0}, 50.0, cars);
  RayHit hit = caster.cast({0, 0, 0.6}, {1, 0, 0}, 100.0, cars, scratch);
  EXPECT_EQ(hit.surface, SurfaceClass::MovingCar);
  EXPECT_NEAR(hit.t, 7.75, 1e-9);
  traffic.primitivesAt(7.0, world.terrain(), {0.0, 0.0}, 50.0, cars);
  hit = caster.cast({0, 0, 0.6}, {1, 0, 0}, 100.0, cars, scratch);
  EXPECT_NEAR(hit.t, 17.75, 1e-9);
}
