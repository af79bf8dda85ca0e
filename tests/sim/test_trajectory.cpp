// Ground truth of the vehicle: continuity, limits, the closed loop and attitude on the ground.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

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
  EXPECT_LT(maxYawRate, 0.7);  // 5.9 m/s on a 10 m radius.
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

namespace {

/// Curvature along one lap from the public state (yaw rate / speed), at arc lengths s in
/// [0, lapLength), sampled finely in time.
struct CurvatureSample {
  double s, curvature;
  Eigen::Vector2d position;
};

std::vector<CurvatureSample> curvatureAlongLap(const Route& route) {
  std::vector<CurvatureSample> out;
  for (double t = 0; t < route.lapDuration(); t += 0.002) {
    const RouteState st = route.stateAt(t);
    out.push_back({st.distance, st.yawRate / st.speed, st.position});
  }
  return out;
}

}  // namespace

TEST(Route, YawRateIsContinuousAndMatchesTheHeadingDerivative) {
  const auto& s = scenario();
  const double dt = 0.01;
  double maxJump = 0, maxMismatch = 0, maxYawRate = 0;
  RouteState prev = s.route.stateAt(0.0);
  for (double t = dt; t < 1.2 * s.route.lapDuration(); t += dt) {
    const RouteState cur = s.route.stateAt(t);
    maxJump = std::max(maxJump, std::abs(cur.yawRate - prev.yawRate));
    // yawRate = curvature * speed must be the derivative of the heading the poses carry.
    const double dHeading = std::remainder(cur.heading - prev.heading, 2 * M_PI) / dt;
    maxMismatch = std::max(maxMismatch, std::abs(dHeading - 0.5 * (cur.yawRate + prev.yawRate)));
    maxYawRate = std::max(maxYawRate, cur.yawRate);
    prev = cur;
  }
  EXPECT_GT(maxYawRate * 180 / M_PI, 30.0);  // The corners are really driven.
  EXPECT_LT(maxJump * 180 / M_PI, 3.0);      // Steering over about a second, no step.
  // Finite differences over 0.01 s and the table's linear interpolation across the curvature's
  // kinks leave ~1e-3 rad/s; a heading out of step with the yaw rate would be far larger.
  EXPECT_LT(maxMismatch, 3e-3);

  // The test sees the step of circular corners (Lt = 0): ~34 deg/s within one sample.
  const WorldParams layout;
  const Route circular = Route::roundedRectangle(layout.loopMin, layout.loopMax, 10.0, 0.0);
  double circularJump = 0;
  prev = circular.stateAt(0.0);
  for (double t = dt; t < circular.lapDuration(); t += dt) {
    const RouteState cur = circular.stateAt(t);
    circularJump = std::max(circularJump, std::abs(cur.yawRate - prev.yawRate));
    prev = cur;
  }
  EXPECT_GT(circularJump * 180 / M_PI, 20.0);
}

TEST(Route, CurvatureRampsLinearlyOverTheTransitionLength) {
  const double R = 10.0, Lt = 8.0;
  const Route route = Route::roundedRectangle({0, 0}, {60, 40}, R, Lt);
  const auto samples = curvatureAlongLap(route);
  // Clothoid series for the corner's tangent length T = R + p + m (p: shift of the arc, m: half
  // the spiral's length less a little): the corner starts T before the rectangle's vertex.
  const double p = Lt * Lt / (24 * R) - std::pow(Lt, 4) / (2688 * std::pow(R, 3)) +
                   std::pow(Lt, 6) / (506880 * std::pow(R, 5));
  const double m =
      Lt / 2 - std::pow(Lt, 3) / (240 * R * R) + std::pow(Lt, 5) / (34560 * std::pow(R, 4));
  const double T = R + p + m;
  EXPECT_NEAR(route.lapLength(), 200.0 - 8 * T + 4 * (Lt + 0.5 * M_PI * R), 1e-4);

  // Straight-line fits of curvature against s over the first corner's ramps, away from their
  // ends (the table interpolates across each kink within one 5 cm step).
  const auto fit = [&](double from, double to, double& a, double& b, double& worst) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto& c : samples) {
      if (c.s < from || c.s > to) continue;
      n += 1, sx += c.s, sy += c.curvature, sxx += c.s * c.s, sxy += c.s * c.curvature;
    }
    b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    a = (sy - b * sx) / n;
    worst = 0;
    for (const auto& c : samples) {
      if (c.s >= from && c.s <= to) worst = std::max(worst, std::abs(c.curvature - a - b * c.s));
    }
  };
  const double sIn = 30.0 - T, sOut = sIn + Lt + 0.5 * M_PI * R;  // Analytic, for the windows.
  double aIn, bIn, worstIn, aOut, bOut, worstOut;
  fit(sIn + 0.2, sIn + Lt - 0.2, aIn, bIn, worstIn);
  fit(sOut - Lt + 0.2, sOut - 0.2, aOut, bOut, worstOut);
  EXPECT_NEAR(bIn, 1.0 / (R * Lt), 1e-3 / (R * Lt));
  EXPECT_NEAR(bOut, -1.0 / (R * Lt), 1e-3 / (R * Lt));
  EXPECT_LT(worstIn, 1e-5);
  EXPECT_LT(worstOut, 1e-5);
  // Where the lines reach 0 and 1 / R: the ramps are Lt long and where the geometry says.
  const double in0 = -aIn / bIn, in1 = (1.0 / R - aIn) / bIn;
  const double out1 = (1.0 / R - aOut) / bOut, out0 = -aOut / bOut;
  EXPECT_NEAR(in0, sIn, 0.01);
  EXPECT_NEAR(in1 - in0, Lt, 0.01);
  EXPECT_NEAR(out1 - in1, 0.5 * M_PI * R - Lt, 0.01);
  EXPECT_NEAR(out0 - out1, Lt, 0.01);
  // Constant 1 / R in between, 0 before and after.
  for (const auto& c : samples) {
    if (c.s > in1 + 0.05 && c.s < out1 - 0.05) {
      EXPECT_NEAR(c.curvature, 1.0 / R, 1e-9) << "s=" << c.s;
    }
    if (c.s < in0 - 0.05 || (c.s > out0 + 0.05 && c.s < sOut + 2 * (20.0 - T) - 0.05)) {
      EXPECT_EQ(c.curvature, 0.0) << "s=" << c.s;
    }
  }
  // Where the curvature is 0, the route is on a side of the rectangle: the straights were
  // shortened by the clothoid corner's displacement, not the arc's R.
  for (const auto& c : samples) {
    if (c.curvature != 0.0) continue;
    const Eigen::Vector2d q = c.position;
    const double offSide = std::min(std::min(std::abs(q.x()), std::abs(q.x() - 60.0)),
                                    std::min(std::abs(q.y()), std::abs(q.y() - 40.0)));
    EXPECT_LT(offSide, 1e-6) << "s=" << c.s;
  }
}
TEST(Route, TransitionLengthIsClampedAndZeroGivesCircularCorners) {
  const double R = 10.0;
  const Route circular = Route::roundedRectangle({0, 0}, {60, 40}, R, 0.0);
  EXPECT_NEAR(circular.lapLength(), 200.0 - 8 * R + 2 * M_PI * R, 1e-9);
  const Route longest = Route::roundedRectangle({0, 0}, {60, 40}, R, 0.5 * M_PI * R);
  const Route clamped = Route::roundedRectangle({0, 0}, {60, 40}, R, 100.0);
  EXPECT_DOUBLE_EQ(clamped.lapLength(), longest.lapLength());
  EXPECT_DOUBLE_EQ(clamped.lapDuration(), longest.lapDuration());
  // Both close the lap.
  for (const Route* r : {&circular, &clamped}) {
    const RouteState a = r->stateAt(0.0), b = r->stateAt(r->lapDuration());
    EXPECT_LT((a.position - b.position).norm(), 1e-9);
    EXPECT_NEAR(std::remainder(a.heading - b.heading, 2 * M_PI), 0.0, 1e-9);
  }
  EXPECT_THROW(Route::roundedRectangle({0, 0}, {60, 40}, 0.0), std::invalid_argument);
  // Corners of 10 m radius and 8 m transitions need about 14.2 m of each half side.
  EXPECT_THROW(Route::roundedRectangle({0, 0}, {60, 25}, R, 8.0), std::invalid_argument);
  EXPECT_NO_THROW(Route::roundedRectangle({0, 0}, {60, 29}, R, 8.0));
}

TEST(Route, APatrolTurnsOnTheSpotAndClosesItsLap) {
  const Route patrol = Route::patrol({0, 0}, {60, 40}, 1.5, 90.0);
  // Two turns round (180 deg each) over 10 m and back, then the rectangle's 200 m.
  EXPECT_NEAR(patrol.lapLength(), 220.0, 1e-9);
  const RouteState start = patrol.stateAt(0.0);
  const RouteState lap = patrol.stateAt(patrol.lapDuration() - 1e-9);
  EXPECT_LT((lap.position - start.position).norm(), 1e-6);
  EXPECT_NEAR(std::remainder(lap.heading - start.heading, 2 * M_PI), 0.0, 1e-6);
  const double dt = 0.01;
  double maxSpeed = 0, maxYawRate = 0, maxSpeedJump = 0, turningSpeed = 0;
  RouteState prev = start;
  for (double t = dt; t < patrol.lapDuration(); t += dt) {
    const RouteState cur = patrol.stateAt(t);
    maxSpeed = std::max(maxSpeed, cur.speed);
    maxYawRate = std::max(maxYawRate, std::abs(cur.yawRate));
    maxSpeedJump = std::max(maxSpeedJump, std::abs(cur.speed - prev.speed));
    if (cur.yawRate != 0.0) {
      // On the spot: no speed, no displacement while turning.
      turningSpeed = std::max(turningSpeed, cur.speed + (cur.position - prev.position).norm());
    }
    prev = cur;
  }
  EXPECT_NEAR(maxSpeed, 1.5, 1e-6);
  EXPECT_NEAR(maxYawRate * 180 / M_PI, 90.0, 1e-6);  // the yaw rate steps to the turn rate
  EXPECT_LT(maxSpeedJump, 1.0 * dt + 1e-9);          // 1 m/s^2 ramps
  EXPECT_LT(turningSpeed, 0.02);
  EXPECT_THROW(Route::patrol({0, 0}, {60, 40}, 0.0, 90.0), std::invalid_argument);
  EXPECT_THROW(Route::patrol({0, 0}, {10, 40}, 1.5, 90.0), std::invalid_argument);
}
