// One LiDAR revolution at a time: firing timing, motion distortion, noise and dropouts.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "dlo/sim/lidar_model.h"
#include "dlo/sim/primitives.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/vehicle_trajectory.h"

namespace dlo::sim {

/// Measurement imperfections.
struct SweepNoise {
  bool enabled = true;               ///< false: exact ranges, no dropouts (for tests).
  double rangeSigma = 0.02;          ///< Gaussian range noise [m].
  double dropoutProbability = 0.03;  ///< A return that is lost although something was hit.
};

/// Everything a SweepSimulator needs besides the world and the trajectory.
struct SweepSimulatorParams {
  LidarModel model = makeLidarModel(SensorType::VLP16);
  SweepNoise noise;
  uint32_t seed = 1;
  int threads = 2;  ///< Worker threads; results do not depend on it.
};

/**
 * One sweep as the sensor reports it: a range image of `firings` columns by `lasers` rows.
 *
 * Per-point time: laser l of firing f fires at
 *   referenceTimeNs + f * model.firingPeriodNs + l * model.laserTimeOffsetNs,
 * and its measurement is taken from the sensor pose at that instant (the motion distortion of
 * a real spinning LiDAR, not compensated). referenceTimeNs is the time of the sweep's first
 * firing; all times count from the start of the sequence.
 */
struct Sweep {
  int64_t frameIndex = 0;
  int64_t firstFiring = 0;      ///< Index of the first firing since the sequence start.
  int64_t referenceTimeNs = 0;  ///< Time of the first firing.
  int firings = 0, lasers = 0;
  std::vector<float> range;  ///< [firing * lasers + laser] in metres; 0 = no return.
  std::vector<uint8_t> intensity;
  std::vector<SurfaceClass> surface;  ///< What was hit (None for no return).

  size_t index(int firing, int laser) const { return static_cast<size_t>(firing) * lasers + laser; }
};

/// Simulates the sweeps of a LiDAR on a vehicle driving through a world.
class SweepSimulator {
 public:
  SweepSimulator(const ProceduralWorld& world, const VehicleTrajectory& trajectory,
                 SweepSimulatorParams params);

  /// Sweep number `frame` (0, 1, ...): the whole data packets that start within
  /// [frame, frame + 1) revolutions.
  Sweep simulate(int64_t frame) const;

  /// Time of laser `laser` of firing `firing` of the sweep [ns since the sequence start].
  int64_t pointTimeNs(const Sweep& sweep, int firing, int laser) const;
  /// Head azimuth at a time [deg in [0, 360)], clockwise from the sensor's +x: each revolution
  /// starts at model().sweepStartDeg and turns in model().spinDirection.
  double azimuthDeg(int64_t timeNs) const;
  /// Unit vector of a laser at a head azimuth, in the sensor frame.
  Eigen::Vector3d beamDirection(int laser, double azimuthDeg) const;
  /// The measured point in the sensor frame at its own time (zero vector for no return).
  Eigen::Vector3d sensorPoint(const Sweep& sweep, int firing, int laser) const;
  /// Pose of the sensor in the world at a time [ns].
  Eigen::Isometry3d sensorPoseAt(int64_t timeNs) const;

  const LidarModel& model() const { return params_.model; }
  int64_t revolutionNs() const { return revolutionNs_; }

 private:
  void simulateFirings(Sweep& sweep, int begin, int end, uint32_t chunk) const;

  const ProceduralWorld& world_;
  const VehicleTrajectory& trajectory_;
  SweepSimulatorParams params_;
  int64_t revolutionNs_ = 100000000;
  std::vector<double> sinElevation_, cosElevation_;
};

}  // namespace dlo::sim
