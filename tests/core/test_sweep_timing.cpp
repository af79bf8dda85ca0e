// Per-point times estimated from azimuths (estimateSweepTimes): synthetic sweeps stored in firing
// order and ring by ring, a shuffled one, and the real KITTI scan.
#include <gtest/gtest.h>

#include <mrpt/maps/CPointsMapXYZI.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "../test_data.h"
#include "dlo/core/sweep_timing.h"
#include "dlo/mrpt/kitti_conversion.h"

namespace dlo {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// A sweep of `lasers` x `firings` points spinning in `direction` from `start_deg`, each laser
/// with an azimuth offset of its own (as a Velodyne's), ranges 3-60 m, and the true time of
/// every point relative to the sweep's middle.
struct SyntheticSweep {
  PointCloud points;
  std::vector<float> truth;
};

/// `turns`: revolutions the sweep covers (a sensor's sweep overlaps itself by a firing or two).
SyntheticSweep makeSweep(int lasers, int firings, int direction, double start_deg, bool ring_order,
                         double period, std::mt19937& rng, double turns = 1.0) {
  std::uniform_real_distribution<double> range(3.0, 60.0), offset(-2.0, 2.0);
  std::vector<double> laser_offset(lasers);
  for (double& o : laser_offset) o = offset(rng);
  SyntheticSweep s;
  const auto add = [&](int l, int f) {
    const double phase = turns * (f + 0.5) / firings;  // fraction of the revolution
    const double az = (start_deg + direction * (360.0 * phase + laser_offset[l])) * kPi / 180.0;
    const double r = range(rng);
    const double elevation = (-24.0 + 26.0 * l / lasers) * kPi / 180.0;
    s.points.emplace_back(static_cast<float>(r * std::cos(elevation) * std::cos(az)),
                          static_cast<float>(r * std::cos(elevation) * std::sin(az)),
                          static_cast<float>(r * std::sin(elevation)));
    // The laser's own offset shifts where it looks, not when it fires; the estimate reads the
    // azimuth, so its truth is the azimuth's phase (errors of 2 deg = 0.6 ms are the offsets').
    s.truth.push_back(static_cast<float>((phase - 0.5) * period));
  };
  if (ring_order) {
    for (int l = 0; l < lasers; ++l)
      for (int f = 0; f < firings; ++f) add(l, f);
  } else {
    for (int f = 0; f < firings; ++f)
      for (int l = 0; l < lasers; ++l) add(l, f);
  }
  return s;
}

/// Fraction of points whose estimated time is within `tolerance` seconds of the truth.
double fractionWithin(const std::vector<float>& est, const std::vector<float>& truth,
                      double tolerance) {
  size_t ok = 0;
  for (size_t i = 0; i < est.size(); ++i) ok += std::fabs(est[i] - truth[i]) <= tolerance;
  return static_cast<double>(ok) / static_cast<double>(est.size());
}

double angleDiffDeg(double a, double b) {
  double d = std::fmod(a - b + 540.0, 360.0) - 180.0;
  return std::fabs(d);
}

TEST(SweepTiming, FiringOrderRevealsDirectionAndStart) {
  std::mt19937 rng(7);
  for (const int direction : {-1, 1}) {
    for (const double start : {180.0, 0.0, 73.0, -120.0}) {
      SCOPED_TRACE("direction " + std::to_string(direction) + " start " + std::to_string(start));
      const SyntheticSweep s = makeSweep(64, 1800, direction, start, false, 0.1, rng);
      SweepTimingParams p;  // deliberately the other direction and start
      p.direction = -direction;
      p.start_azimuth_deg = start + 90.0;
      std::vector<float> times;
      const SweepTimingEstimate e = estimateSweepTimes(s.points, p, times);
      EXPECT_TRUE(e.from_order);
      EXPECT_EQ(e.direction, direction);
      EXPECT_LT(angleDiffDeg(e.start_azimuth_deg, start), 1.0);
      ASSERT_EQ(times.size(), s.points.size());
      // Within the lasers' azimuth offsets (2 deg: 0.56 ms) and the start's error (1 deg), except
      // the few points whose offset carries them across the seam.
      EXPECT_GT(fractionWithin(times, s.truth, 0.0009), 0.99);
    }
  }
}

TEST(SweepTiming, InFiringOrderThePointsAtTheSeamKeepTheirEndOfTheSweep) {
  // Near the seam the azimuth is the same at both ends of a sweep: the lasers' own azimuth
  // offsets (2 deg) put some of the first firing's points beyond the start, and a sweep that
  // overlaps itself by a degree repeats the first azimuths at its end. Timed by azimuth alone,
  // those points were a whole period off (at 10 m/s, a metre once deskewed); their place in the
  // cloud tells which end they belong to.
  std::mt19937 rng(5);
  for (const int direction : {-1, 1}) {
    SCOPED_TRACE("direction " + std::to_string(direction));
    const SyntheticSweep s = makeSweep(32, 1800, direction, 0.0, false, 0.1, rng, 361.0 / 360.0);
    SweepTimingParams p;
    std::vector<float> times;
    const SweepTimingEstimate e = estimateSweepTimes(s.points, p, times);
    ASSERT_TRUE(e.from_order);
    float worst = 0.0f;
    for (size_t i = 0; i < times.size(); ++i)
      worst = std::max(worst, std::fabs(times[i] - s.truth[i]));
    // The offsets (0.56 ms), the start's error and the overlap (0.3 ms): never a period.
    EXPECT_LT(worst, 0.002f);
    // The scalar tail (a cloud whose size is not a multiple of four) agrees.
    PointCloud odd(s.points.begin(), s.points.end() - 3);
    std::vector<float> odd_times;
    estimateSweepTimes(odd, p, odd_times);
    EXPECT_LT(std::fabs(odd_times.back() - s.truth[odd.size() - 1]), 0.002f);
  }
}

TEST(SweepTiming, RingByRingOrderIsNotTakenForTime) {
  // KITTI's files hold one laser's ring after another, each running counter-clockwise from the
  // front although the sensor spins clockwise from behind: such an order says nothing of time,
  // and the parameters decide.
  std::mt19937 rng(11);
  const SyntheticSweep s = makeSweep(32, 1500, 1, 0.0, true, 0.1, rng);
  SweepTimingParams p;
  p.direction = 1;
  p.start_azimuth_deg = 0.0;
  std::vector<float> times;
  const SweepTimingEstimate e = estimateSweepTimes(s.points, p, times);
  EXPECT_FALSE(e.from_order);
  EXPECT_EQ(e.direction, 1);
  EXPECT_DOUBLE_EQ(e.start_azimuth_deg, 0.0);
  EXPECT_GT(fractionWithin(times, s.truth, 0.0006), 0.99);
}

TEST(SweepTiming, AShuffledCloudFallsBackOnTheParameters) {
  std::mt19937 rng(3);
  SyntheticSweep s = makeSweep(16, 1800, -1, 180.0, false, 0.1, rng);
  std::vector<size_t> order(s.points.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  PointCloud shuffled;
  std::vector<float> truth;
  for (const size_t i : order) {
    shuffled.push_back(s.points[i]);
    truth.push_back(s.truth[i]);
  }
  std::vector<float> times;
  SweepTimingParams p;  // the right ones: clockwise from behind, stamped in the middle
  SweepTimingEstimate e = estimateSweepTimes(shuffled, p, times);
  EXPECT_FALSE(e.from_order);
  EXPECT_EQ(e.direction, -1);
  EXPECT_DOUBLE_EQ(e.start_azimuth_deg, 180.0);
  EXPECT_GT(fractionWithin(times, truth, 0.0006), 0.99);
  // Wrong parameters give wrong times: the estimate does follow them.
  p.direction = 1;
  e = estimateSweepTimes(shuffled, p, times);
  EXPECT_EQ(e.direction, 1);
  EXPECT_LT(fractionWithin(times, truth, 0.0006), 0.1);
}

TEST(SweepTiming, StampPhaseAndPeriodScaleTheTimes) {
  std::mt19937 rng(5);
  const SyntheticSweep s = makeSweep(16, 900, -1, 180.0, false, 0.05, rng);
  SweepTimingParams p;
  p.period = 0.05;
  p.stamp_phase = 0.0;  // stamped at the first point: times in [0, period)
  std::vector<float> times;
  estimateSweepTimes(s.points, p, times);
  std::vector<float> truth = s.truth;
  for (float& t : truth) t += 0.025f;
  EXPECT_GT(fractionWithin(times, truth, 0.0003), 0.99);
  // Within [0, period), up to the lasers' azimuth offsets (2 deg, 0.28 ms) that carry the first
  // and last firings' points across the seam.
  EXPECT_GE(*std::min_element(times.begin(), times.end()), -0.0003f);
  EXPECT_LT(*std::max_element(times.begin(), times.end()), 0.0503f);
}

TEST(SweepTiming, NonFiniteAndTinyCloudsAreHandled) {
  PointCloud points(10, Eigen::Vector3f(1.0f, 1.0f, 0.0f));
  points[3] = Eigen::Vector3f(std::nanf(""), 0.0f, 0.0f);
  std::vector<float> times;
  const SweepTimingEstimate e = estimateSweepTimes(points, SweepTimingParams(), times);
  EXPECT_FALSE(e.from_order);  // too few points to read an order from
  ASSERT_EQ(times.size(), points.size());
  EXPECT_EQ(times[3], 0.0f);
  for (const float t : times) EXPECT_TRUE(std::isfinite(t));
  estimateSweepTimes(PointCloud(), SweepTimingParams(), times);
  EXPECT_TRUE(times.empty());
}

TEST(SweepTiming, TheRealKittiScanIsTimedClockwiseFromBehind) {
  // KITTI's HDL-64E spins clockwise seen from above and its sweeps begin and end behind the car
  // (the camera is triggered when the head faces forward, mid-sweep).
  mrpt::maps::CPointsMapXYZI map;
  loadKittiBinXYZI(test::sharedData("kitti_00_000000.bin.gz"), map);
  PointCloud points;
  for (size_t i = 0; i < map.size(); ++i) {
    float x, y, z;
    map.getPointFast(i, x, y, z);
    points.emplace_back(x, y, z);
  }
  // Its rings are stored counter-clockwise from the front: not the order of time, so the
  // defaults (KITTI's convention) decide.
  std::vector<float> times;
  const SweepTimingEstimate e = estimateSweepTimes(points, SweepTimingParams(), times);
  EXPECT_FALSE(e.from_order);
  EXPECT_EQ(e.direction, -1);
  EXPECT_DOUBLE_EQ(e.start_azimuth_deg, 180.0);
  // Points ahead are measured mid-sweep, points to the left (clockwise from behind) before.
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    if (p.head<2>().norm() < 5.0f) continue;
    if (p.x() > 0.0f && std::fabs(p.y()) < 0.05f * p.x()) {
      EXPECT_NEAR(times[i], 0.0f, 0.003f);
    } else if (p.y() > 0.0f && std::fabs(p.x()) < 0.05f * p.y()) {
      EXPECT_NEAR(times[i], -0.025f, 0.003f);
    }
  }
}

TEST(SweepPeriodEstimate, IsTheMedianIntervalBetweenScans) {
  SweepPeriodEstimate e;
  EXPECT_FALSE(e.known());
  EXPECT_DOUBLE_EQ(e.period(0.1), 0.1);  // one timestamp tells nothing
  e.add(100.0);
  EXPECT_DOUBLE_EQ(e.period(0.1), 0.1);
  // A 20 Hz sensor with a little jitter, a dropped scan and a repeated stamp.
  double t = 100.0;
  for (int k = 1; k <= 30; ++k) {
    t += (k == 12 ? 0.1 : 0.05) + (k % 2 ? 2e-4 : -2e-4);
    e.add(t);
    if (k == 20) e.add(t);  // the same stamp twice: ignored
  }
  ASSERT_TRUE(e.known());
  EXPECT_NEAR(e.period(0.1), 0.05, 3e-4);
}

TEST(SweepPeriodEstimate, IgnoresGapsAndAveragesStampsCutAtPackets) {
  SweepPeriodEstimate e;
  double t = 0.0;
  e.add(t);
  e.add(t += 5.0);  // a pause in the recording: not a period
  EXPECT_FALSE(e.known());
  // A 5 Hz sensor whose sweeps end at packet boundaries: 200.8, 199.5, 199.7 ms, ... The
  // median of such a pattern is one of its values; the mean is the period.
  const double pattern[] = {0.2008, 0.1995, 0.1997};
  for (int k = 0; k < 60; ++k) e.add(t += pattern[k % 3]);
  EXPECT_NEAR(e.period(0.1), 0.2, 1e-9);
  e.add(t += 0.4);  // a dropped scan
  EXPECT_NEAR(e.period(0.1), 0.2, 1e-4);
}

}  // namespace
}  // namespace dlo
