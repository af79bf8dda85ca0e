#include "dlo/sim/sweep_simulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "dlo/sim/deterministic_random.h"
#include "dlo/sim/ray_caster.h"

namespace dlo::sim {

namespace {

/// Firings per unit of work. Each unit draws from its own random stream, so the noise does not
/// depend on how units are spread over threads.
constexpr int kChunkFirings = 64;

/// Diffuse reflectivity by material, in [0, 1].
double reflectivity(SurfaceClass s) {
  switch (s) {
    case SurfaceClass::Road:
      return 0.12;
    case SurfaceClass::Sidewalk:
      return 0.35;
    case SurfaceClass::Grass:
      return 0.25;
    case SurfaceClass::Building:
      return 0.55;
    case SurfaceClass::Roof:
      return 0.4;
    case SurfaceClass::Trunk:
      return 0.3;
    case SurfaceClass::Foliage:
      return 0.2;
    case SurfaceClass::Pole:
      return 0.8;
    case SurfaceClass::Car:
    case SurfaceClass::MovingCar:
      return 0.7;
    case SurfaceClass::None:
      break;
  }
  return 0.0;
}

int64_t ceilDiv(int64_t a, int64_t b) {
  return (a + b - 1) / b;
}

}  // namespace

SweepSimulator::SweepSimulator(const ProceduralWorld& world, const VehicleTrajectory& trajectory,
                               SweepSimulatorParams params)
    : world_(world), trajectory_(trajectory), params_(std::move(params)) {
  revolutionNs_ = std::llround(1e9 / params_.model.rotationHz);
  for (double e : params_.model.elevationDeg) {
    sinElevation_.push_back(std::sin(e * M_PI / 180.0));
    cosElevation_.push_back(std::cos(e * M_PI / 180.0));
  }
}

int64_t SweepSimulator::pointTimeNs(const Sweep& sweep, int firing, int laser) const {
  return (sweep.firstFiring + firing) * params_.model.firingPeriodNs +
         laser * params_.model.laserTimeOffsetNs;
}

double SweepSimulator::azimuthDeg(int64_t timeNs) const {
  const LidarModel& m = params_.model;
  // Degrees turned since the sweep's start, then clockwise from +x. The default (start 0,
  // clockwise) is the turned angle itself, to the bit: -0.0 + x == x and fmod is exact.
  const double turned =
      360.0 * static_cast<double>(timeNs % revolutionNs_) / static_cast<double>(revolutionNs_);
  const double clockwise =
      std::fmod(-m.sweepStartDeg + (m.spinDirection < 0 ? turned : -turned), 360.0);
  return clockwise < 0.0 ? clockwise + 360.0 : clockwise;
}

Eigen::Vector3d SweepSimulator::beamDirection(int laser, double azimuthDeg) const {
  const double a = azimuthDeg * M_PI / 180.0;
  const double c = cosElevation_[laser];
  return Eigen::Vector3d(c * std::cos(a), -c * std::sin(a), sinElevation_[laser]);
}

Eigen::Vector3d SweepSimulator::sensorPoint(const Sweep& sweep, int firing, int laser) const {
  const float r = sweep.range[sweep.index(firing, laser)];
  if (r <= 0.0f) return Eigen::Vector3d::Zero();
  return r * beamDirection(laser, azimuthDeg(pointTimeNs(sweep, firing, laser)));
}

Eigen::Isometry3d SweepSimulator::sensorPoseAt(int64_t timeNs) const {
  return trajectory_.vehiclePose(static_cast<double>(timeNs) * 1e-9) * trajectory_.sensorMount();
}

Sweep SweepSimulator::simulate(int64_t frame) const {
  const LidarModel& m = params_.model;
  const int64_t packetNs = m.packetPeriodNs();
  const int64_t p0 = ceilDiv(frame * revolutionNs_, packetNs);
  const int64_t p1 = ceilDiv((frame + 1) * revolutionNs_, packetNs);
  Sweep sweep;
  sweep.frameIndex = frame;
  sweep.firstFiring = p0 * m.firingsPerPacket;
  sweep.referenceTimeNs = sweep.firstFiring * m.firingPeriodNs;
  sweep.firings = static_cast<int>((p1 - p0) * m.firingsPerPacket);
  sweep.lasers = m.laserCount();
  const size_t n = static_cast<size_t>(sweep.firings) * sweep.lasers;
  sweep.range.assign(n, 0.0f);
  sweep.intensity.assign(n, 0);
  sweep.surface.assign(n, SurfaceClass::None);

  const int chunks = (sweep.firings + kChunkFirings - 1) / kChunkFirings;
  std::atomic<int> next{0};
  const auto work = [&]() {
    for (int c = next++; c < chunks; c = next++) {
      simulateFirings(sweep, c * kChunkFirings, std::min(sweep.firings, (c + 1) * kChunkFirings),
                      static_cast<uint32_t>(c));
    }
  };
  const int threads = std::max(1, std::min(params_.threads, chunks));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
  return sweep;
}

void SweepSimulator::simulateFirings(Sweep& sweep, int begin, int end, uint32_t chunk) const {
  const LidarModel& m = params_.model;
  const SweepNoise& noise = params_.noise;
  DeterministicRng rng({params_.seed, static_cast<uint32_t>(sweep.frameIndex),
                        static_cast<uint32_t>(sweep.frameIndex >> 32), chunk, 0x4c494452u});
  RayCaster caster(world_);
  GridScratch scratch;
  std::vector<Primitive> cars;
  for (int f = begin; f < end; ++f) {
    const int64_t tFiring = pointTimeNs(sweep, f, 0);
    Eigen::Isometry3d pose = sensorPoseAt(tFiring);
    world_.traffic().primitivesAt(static_cast<double>(tFiring) * 1e-9, world_.terrain(),
                                  pose.translation().head<2>(), m.maxRange + 5.0, cars);
    for (int l = 0; l < sweep.lasers; ++l) {
      const int64_t t = pointTimeNs(sweep, f, l);
      // Each laser sees the world from where the sensor is when it fires.
      if (l > 0 && m.laserTimeOffsetNs != 0) pose = sensorPoseAt(t);
      const Eigen::Vector3d dir = pose.linear() * beamDirection(l, azimuthDeg(t));
      const RayHit hit = caster.cast(pose.translation(), dir, m.maxRange, cars, scratch);
      // Always the same draws per ray, so that one ray's outcome does not shift the others.
      const double drop = rng.uniform01();
      const double err = rng.gaussian(0.0, noise.rangeSigma);
      const double shade = rng.uniform(0.9, 1.1);
      if (!hit.valid()) continue;
      double r = hit.t;
      if (noise.enabled) {
        if (drop < noise.dropoutProbability) continue;
        r += err;
      }
      if (r < m.minRange || r > m.maxRange) continue;
      const size_t k = sweep.index(f, l);
      sweep.range[k] = static_cast<float>(r);
      sweep.surface[k] = hit.surface;
      const double falloff = 0.6 + 0.4 * (1.0 - r / m.maxRange);
      const double value =
          255.0 * reflectivity(hit.surface) * falloff * (noise.enabled ? shade : 1.0);
      sweep.intensity[k] = static_cast<uint8_t>(std::clamp(value, 1.0, 255.0));
    }
  }
}

}  // namespace dlo::sim
