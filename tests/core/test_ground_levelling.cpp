// The ground of a scan and z, roll and pitch from it: fitGroundSurface() on synthetic ground
// that climbs to a crest and falls away beyond it, with a car, a wall and a tree canopy standing
// on it; alignToGround() recovering the height, roll and pitch that a planar estimate misses,
// keeping the guess where the ground cannot tell.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "dlo/core/ground_alignment.h"
#include "dlo/core/ground_surface.h"
#include "dlo/core/height_grid.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/units.h"

namespace dlo {
namespace {

/// The world's ground: climbing at 15 % at x = 0 to a crest at x = 7.5 m and falling at 25 %
/// at x = 20 m, with a 3 % cross slope.
double ground(double x, double y) {
  return 0.15 * x - 0.01 * x * x + 0.03 * y;
}
Eigen::Vector2d groundGradient(double x, double) {
  return {0.15 - 0.02 * x, 0.03};
}

/// A vehicle standing on the ground at (x, y) heading `yaw`: its z axis along the ground's
/// normal, its origin on the ground.
Eigen::Isometry3d standing(double x, double y, double yaw) {
  const Eigen::Vector2d g = groundGradient(x, y);
  const Eigen::Vector3d up = Eigen::Vector3d(-g.x(), -g.y(), 1.0).normalized();
  const Eigen::Vector3d heading(std::cos(yaw), std::sin(yaw), 0.0);
  const Eigen::Vector3d left = up.cross(heading).normalized();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = left.cross(up);
  T.linear().col(1) = left;
  T.linear().col(2) = up;
  T.translation() = Eigen::Vector3d(x, y, ground(x, y));
  return T;
}

/// The car's footprint (world x, y) and the canopy's centre and radius.
constexpr double kCarX0 = 4.0, kCarX1 = 8.5, kCarY0 = 2.5, kCarY1 = 4.5;
const Eigen::Vector2d kCanopy(-5.0, 6.0);
constexpr double kCanopyRadius = 2.5;

/// Points of the world within 24 m of `centre`: ground with 2 cm noise, a car (1.5 m roof and
/// sides), a 4 m wall along y = -8 and a canopy 4-5 m above the ground (over ground that is
/// also seen, so its cells mix both).
PointCloud worldPoints(const Eigen::Vector2d& centre, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.02);
  PointCloud pts;
  const auto add = [&](double x, double y, double z) {
    if ((Eigen::Vector2d(x, y) - centre).norm() < 24.0) pts.emplace_back(x, y, z);
  };
  for (int i = 0; i < 120000; ++i) {
    const double x = centre.x() + 48.0 * unit(rng) - 24.0, y = centre.y() + 48.0 * unit(rng) - 24.0;
    const bool under_car = x > kCarX0 && x < kCarX1 && y > kCarY0 && y < kCarY1;
    if (!under_car) add(x, y, ground(x, y) + noise(rng));
  }
  for (int i = 0; i < 20000; ++i) {
    const double x = kCarX0 + (kCarX1 - kCarX0) * unit(rng), y = kCarY0 + 2.0 * unit(rng);
    add(x, y, ground(x, y) + 1.5);
    add(x, kCarY0, ground(x, kCarY0) + 1.5 * unit(rng));
  }
  for (int i = 0; i < 30000; ++i) {
    const double x = -12.0 + 24.0 * unit(rng);
    add(x, -8.0, ground(x, -8.0) + 4.0 * unit(rng));
  }
  for (int i = 0; i < 20000; ++i) {
    const double r = kCanopyRadius * std::sqrt(unit(rng)), a = 2.0 * M_PI * unit(rng);
    const double x = kCanopy.x() + r * std::cos(a), y = kCanopy.y() + r * std::sin(a);
    add(x, y, ground(x, y) + 4.0 + unit(rng));
  }
  return pts;
}

/// `points` (world) as seen from `pose`, rasterised into 0.4 m cells around it.
HeightGrid gridFrom(const PointCloud& points, const Eigen::Isometry3d& pose) {
  const Eigen::Isometry3f inv = pose.inverse().cast<float>();
  PointCloud local;
  for (const Eigen::Vector3f& p : points) local.push_back(inv * p);
  return HeightGrid::fromPoints(local, GridGeometry::centred(100, 100, 0.4), 3, -10.0, 10.0);
}

/// Roll and pitch of a rotation, radians.
Eigen::Vector2d rollPitch(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d ypr = yawPitchRoll(T.linear());
  return {ypr(2), ypr(1)};
}

class GroundLevelling : public ::testing::Test {
 protected:
  // The reference: a scan from a vehicle at the origin; the current scan 3 m on, up the slope
  // towards the crest and turned by 0.2 rad.
  const Eigen::Isometry3d ref_pose = standing(0.0, 0.0, 0.0);
  const Eigen::Isometry3d cur_pose = standing(3.0, 0.5, 0.2);
  const HeightGrid reference = gridFrom(worldPoints({0.0, 0.0}, 1), ref_pose);
  const HeightGrid current = gridFrom(worldPoints({3.0, 0.5}, 2), cur_pose);
  /// The current scan in the reference's frame.
  const Eigen::Isometry3d truth = ref_pose.inverse() * cur_pose;
};

TEST_F(GroundLevelling, FitKeepsTheGroundAndLeavesOutTheCarTheWallAndTheCanopy) {
  GroundSurface g;
  fitGroundSurface(current, GroundSurfaceParams(), g);
  ASSERT_TRUE(g.found);
  EXPECT_EQ(g.cells.size(), static_cast<size_t>(GroundSurfaceParams().max_cells));
  double worst = 0.0, sum = 0.0;
  int on_objects = 0;
  for (const GroundCell& c : g.cells) {
    const Eigen::Vector3d w = cur_pose * Eigen::Vector3d(c.x, c.y, c.h);
    // The cell's height against the true ground at its centre (the cell's mean is that of
    // a 0.4 m patch of a curved surface: a centimetre at most).
    const double e = w.z() - ground(w.x(), w.y());
    worst = std::max(worst, std::abs(e));
    sum += std::abs(e);
    const bool on_car = w.x() > kCarX0 + 0.5 && w.x() < kCarX1 - 0.5 && w.y() > kCarY0 + 0.5 &&
                        w.y() < kCarY1 - 0.5;
    const bool under_canopy = (w.head<2>() - kCanopy).norm() < kCanopyRadius - 0.5;
    const bool on_wall = std::abs(w.y() + 8.0) < 0.2 && std::abs(w.x()) < 11.5;
    if (on_car || under_canopy || on_wall) ++on_objects;
  }
  EXPECT_EQ(on_objects, 0);
  EXPECT_LT(sum / g.cells.size(), 0.02);
  EXPECT_LT(worst, 0.15);
  // The surface follows the crest: 20 m ahead of the vehicle (x = 21.6 m in the world, past
  // the crest) it lies on the ground, not on the vehicle's plane.
  const Eigen::Vector3d ahead = cur_pose * Eigen::Vector3d(18.0, 0.0, g.heightAt(18.0, 0.0));
  EXPECT_NEAR(ahead.z(), ground(ahead.x(), ahead.y()), 0.15);
}

TEST_F(GroundLevelling, AlignmentRecoversHeightRollAndPitchThatThePlanarGuessMisses) {
  GroundSurface g;
  fitGroundSurface(current, GroundSurfaceParams(), g);
  ASSERT_TRUE(g.found);
  // What a planar odometry keeps: x, y and heading right, level and at the reference's height
  // (plus 0.3 m, more than the robust kernel).
  Eigen::Isometry3d guess = poseFromXYZYPR(truth.translation().x(), truth.translation().y(), 0.3,
                                           yawPitchRoll(truth.linear())(0), 0.0, 0.0);
  ASSERT_GT(std::abs(truth.translation().z() - guess.translation().z()), 0.3);
  ASSERT_GT(std::abs(rollPitch(truth)(1) - rollPitch(guess)(1)), 2.0 * kDeg);
  const GroundAlignment a = alignToGround(reference, g.cells, guess, 10.0);
  ASSERT_TRUE(a.aligned);
  EXPECT_GT(a.cells, 300);
  EXPECT_NEAR(a.pose.translation().z(), truth.translation().z(), 0.02);
  EXPECT_NEAR(rollPitch(a.pose)(0), rollPitch(truth)(0), 0.2 * kDeg);
  EXPECT_NEAR(rollPitch(a.pose)(1), rollPitch(truth)(1), 0.2 * kDeg);
  // x, y and the heading are held.
  EXPECT_NEAR((a.pose.translation() - truth.translation()).head<2>().norm(), 0.0, 0.02);
  EXPECT_NEAR(yawPitchRoll(a.pose.linear())(0), yawPitchRoll(truth.linear())(0), 0.1 * kDeg);
  EXPECT_LT(a.rms, 0.03);
  // The covariance: the height and tilts measured to millimetres and hundredths of a degree
  // (at the vehicle, where the graph's edge is), x, y and the heading left to the registration.
  const Eigen::Matrix<double, 6, 6>& c = a.covariance;
  const Eigen::Vector3d p = a.pose.translation();
  Eigen::Matrix<double, 6, 6> at_vehicle = Eigen::Matrix<double, 6, 6>::Identity();
  at_vehicle.topRightCorner<3, 3>() << 0, -p.z(), p.y(), p.z(), 0, -p.x(), -p.y(), p.x(), 0;
  const Eigen::Matrix<double, 6, 6> v = at_vehicle * c * at_vehicle.transpose();
  EXPECT_GT(v(2, 2), 0.0);
  EXPECT_LT(std::sqrt(v(2, 2)), 0.005);
  EXPECT_LT(std::sqrt(v(3, 3)), 0.05 * kDeg);
  EXPECT_LT(std::sqrt(v(4, 4)), 0.05 * kDeg);
  EXPECT_EQ(c(5, 5), 0.0);
  EXPECT_LT(std::abs(v(0, 0)) + std::abs(v(1, 1)), 1e-8);  // rounding of the lever arm
}

TEST_F(GroundLevelling, AStripOfGroundKeepsTheRollItCannotSee) {
  GroundSurfaceParams every;
  every.max_cells = 100000;
  GroundSurface g;
  fitGroundSurface(current, every, g);
  ASSERT_TRUE(g.found);
  // Only a strip along the vehicle's x axis: the roll across it is unobservable.
  std::vector<GroundCell> strip;
  for (const GroundCell& c : g.cells) {
    if (std::abs(c.y) < 0.7) strip.push_back(c);
  }
  ASSERT_GT(strip.size(), 40u);
  const Eigen::Vector3d ypr = yawPitchRoll(truth.linear());
  const double wrong_roll = rollPitch(truth)(0) + 1.0 * kDeg;
  const Eigen::Isometry3d guess =
      poseFromXYZYPR(truth.translation().x(), truth.translation().y(),
                     truth.translation().z() + 0.1, ypr(0), 0.0, wrong_roll);
  const GroundAlignment a = alignToGround(reference, strip, guess, 10.0);
  ASSERT_TRUE(a.aligned);
  EXPECT_NEAR(a.pose.translation().z(), truth.translation().z(), 0.03);
  EXPECT_NEAR(rollPitch(a.pose)(1), rollPitch(truth)(1), 0.3 * kDeg);
  EXPECT_NEAR(rollPitch(a.pose)(0), wrong_roll, 0.05 * kDeg);
  // The roll it cannot see is not measured: variance 1e6 in the solve's scaled coordinates,
  // along a direction that is mostly roll.
  EXPECT_GT(a.covariance(3, 3), 1e3);
  EXPECT_GT(a.covariance(3, 3), 10.0 * a.covariance(4, 4));
}

TEST_F(GroundLevelling, NoGroundKeepsTheGuess) {
  // A reference that measured nothing where the current ground lies, and no ground at all.
  const HeightGrid empty =
      HeightGrid::fromPoints({}, GridGeometry::centred(100, 100, 0.4), 3, -10.0, 10.0);
  GroundSurface g;
  fitGroundSurface(current, GroundSurfaceParams(), g);
  const Eigen::Isometry3d guess = poseFromXYZYPR(3.0, 0.5, 0.2, 0.2, 0.01, -0.01);
  const GroundAlignment a = alignToGround(empty, g.cells, guess, 10.0);
  EXPECT_FALSE(a.aligned);
  EXPECT_TRUE(a.pose.isApprox(guess));
  GroundSurface none;
  fitGroundSurface(empty, GroundSurfaceParams(), none);
  EXPECT_FALSE(none.found);
  EXPECT_TRUE(none.cells.empty());
  EXPECT_FALSE(alignToGround(reference, none.cells, guess, 10.0).aligned);
}

}  // namespace
}  // namespace dlo
