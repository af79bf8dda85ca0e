// Sensor models and the deterministic random numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "dlo/sim/deterministic_random.h"
#include "dlo/sim/lidar_model.h"

using namespace dlo::sim;

namespace {

double minElevation(const LidarModel& m) {
  return *std::min_element(m.elevationDeg.begin(), m.elevationDeg.end());
}
double maxElevation(const LidarModel& m) {
  return *std::max_element(m.elevationDeg.begin(), m.elevationDeg.end());
}

}  // namespace

TEST(LidarModel, Vlp16HasSixteenLasersFromMinus15To15EveryTwoDegrees) {
  const LidarModel m = makeLidarModel(SensorType::VLP16);
  ASSERT_EQ(m.laserCount(), 16);
  std::vector<double> e = m.elevationDeg;
  std::sort(e.begin(), e.end());
  for (int k = 0; k < 16; ++k) EXPECT_DOUBLE_EQ(e[k], -15.0 + 2.0 * k);
  EXPECT_NEAR(m.azimuthResolutionDeg(), 0.2, 0.005);
  EXPECT_DOUBLE_EQ(m.maxRange, 100.0);
}

TEST(LidarModel, Hdl32HasThirtyTwoLasersFromMinus30p67To10p67) {
  const LidarModel m = makeLidarModel(SensorType::HDL32);
  ASSERT_EQ(m.laserCount(), 32);
  EXPECT_DOUBLE_EQ(minElevation(m), -30.67);
  EXPECT_DOUBLE_EQ(maxElevation(m), 10.67);
  std::vector<double> e = m.elevationDeg;
  std::sort(e.begin(), e.end());
  for (int k = 1; k < 32; ++k) EXPECT_NEAR(e[k] - e[k - 1], 4.0 / 3.0, 0.011);
  EXPECT_NEAR(m.azimuthResolutionDeg(), 0.166, 0.002);
  EXPECT_DOUBLE_EQ(m.maxRange, 70.0);
}

TEST(LidarModel, Hdl64HasSixtyFourLasersFromPlus2ToMinus24p9) {
  const LidarModel m = makeLidarModel(SensorType::HDL64);
  ASSERT_EQ(m.laserCount(), 64);
  EXPECT_NEAR(maxElevation(m), 2.0, 1e-9);
  EXPECT_NEAR(minElevation(m), -24.9, 1e-9);
  // Upper block denser than the lower one.
  EXPECT_NEAR(m.elevationDeg[0] - m.elevationDeg[1], 1.0 / 3.0, 1e-9);
  EXPECT_NEAR(m.elevationDeg[32] - m.elevationDeg[33], 0.518, 0.001);
  EXPECT_NEAR(m.azimuthResolutionDeg(), 0.17, 0.005);
  EXPECT_DOUBLE_EQ(m.maxRange, 120.0);
}

TEST(LidarModel, OusterLikeSensorsSpreadTheirBeamsEvenlyOver45DegreesIn1024Columns) {
  for (const auto& [type, beams] : {std::pair{SensorType::OS64, 64}, {SensorType::OS128, 128}}) {
    const LidarModel m = makeLidarModel(type);
    ASSERT_EQ(m.laserCount(), beams) << m.name;
    EXPECT_FALSE(m.velodyne()) << m.name;
    // Beam 0 the highest, then evenly down to -22.5 deg.
    EXPECT_NEAR(m.elevationDeg.front(), 22.5, 1e-12) << m.name;
    EXPECT_NEAR(m.elevationDeg.back(), -22.5, 1e-12) << m.name;
    for (int k = 1; k < beams; ++k) {
      ASSERT_NEAR(m.elevationDeg[k - 1] - m.elevationDeg[k], 45.0 / (beams - 1), 1e-12) << k;
    }
    // 1024 columns per revolution at 10 Hz, every beam of a column at once.
    EXPECT_EQ(1e9 / m.rotationHz / m.firingPeriodNs, 1024.0) << m.name;
    EXPECT_NEAR(m.rotationHz, 10.0, 1e-4) << m.name;
    EXPECT_EQ(m.laserTimeOffsetNs, 0) << m.name;
    EXPECT_DOUBLE_EQ(m.azimuthResolutionDeg(), 360.0 / 1024.0) << m.name;
    EXPECT_DOUBLE_EQ(m.minRange, 0.5) << m.name;
    EXPECT_DOUBLE_EQ(m.maxRange, 120.0) << m.name;
  }
  EXPECT_TRUE(makeLidarModel(SensorType::HDL64).velodyne());
}

TEST(LidarModel, PacketsHoldWholeFiringsAndTenHertzIsAboutOneRevolution) {
  for (SensorType t : {SensorType::VLP16, SensorType::HDL32, SensorType::HDL64}) {
    const LidarModel m = makeLidarModel(t);
    // 12 blocks of 32 returns per packet.
    EXPECT_EQ(m.firingsPerPacket * m.laserCount(), 12 * 32) << m.name;
    const double firingsPerRev = 1e9 / m.rotationHz / m.firingPeriodNs;
    EXPECT_GT(firingsPerRev, 1700) << m.name;
    EXPECT_LT(firingsPerRev, 2300) << m.name;
  }
}

TEST(LidarModel, ParsesSensorNamesAndRejectsOthers) {
  EXPECT_EQ(parseSensorType("HDL64"), SensorType::HDL64);
  EXPECT_EQ(parseSensorType("hdl-32e"), SensorType::HDL32);
  EXPECT_EQ(parseSensorType("VLP-16"), SensorType::VLP16);
  EXPECT_EQ(parseSensorType("OS64"), SensorType::OS64);
  EXPECT_EQ(parseSensorType("os1-64"), SensorType::OS64);
  EXPECT_EQ(parseSensorType("OS128"), SensorType::OS128);
  EXPECT_EQ(parseSensorType("OS1-128"), SensorType::OS128);
  EXPECT_FALSE(parseSensorType("OS1").has_value());
  EXPECT_FALSE(parseSensorType("OS32").has_value());
  EXPECT_FALSE(parseSensorType("").has_value());
}

TEST(DeterministicRng, SameSeedsGiveTheSameSequenceAndOthersDiffer) {
  DeterministicRng a({1, 2, 3}), b({1, 2, 3}), c({1, 2, 4});
  int differ = 0;
  for (int k = 0; k < 100; ++k) {
    const double x = a.gaussian(0.0, 1.0), y = b.gaussian(0.0, 1.0), z = c.gaussian(0.0, 1.0);
    EXPECT_EQ(x, y);
    differ += x != z;
  }
  EXPECT_GT(differ, 90);
}

TEST(DeterministicRng, DistributionsHaveTheRightMoments) {
  DeterministicRng rng(42);
  const int n = 200000;
  double sum = 0, sum2 = 0, usum = 0;
  int lo = 0, hi = 0;
  for (int k = 0; k < n; ++k) {
    const double g = rng.gaussian(1.0, 0.02);
    sum += g;
    sum2 += (g - 1.0) * (g - 1.0);
    const double u = rng.uniform01();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    usum += u;
    const int i = rng.integer(3, 5);
    ASSERT_GE(i, 3);
    ASSERT_LE(i, 5);
    lo += i == 3;
    hi += i == 5;
  }
  EXPECT_NEAR(sum / n, 1.0, 2e-4);
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.02, 2e-4);
  EXPECT_NEAR(usum / n, 0.5, 0.005);
  EXPECT_NEAR(static_cast<double>(lo) / n, 1.0 / 3.0, 0.01);
  EXPECT_NEAR(static_cast<double>(hi) / n, 1.0 / 3.0, 0.01);
}
