// Geometry and timing of the simulated rotating LiDARs (Velodyne VLP-16, HDL-32E, HDL-64E and
// Ouster-like 64 and 128 beams).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dlo::sim {

/// The sensors the simulator knows.
enum class SensorType { VLP16, HDL32, HDL64, OS64, OS128 };

/**
 * A spinning multi-beam LiDAR: elevation table, firing timing and range limits.
 *
 * A "firing" fires every laser once (laser k at firing time + k * laserTimeOffsetNs), firings
 * repeat every firingPeriodNs while the head spins at rotationHz. For the Velodyne sensors the
 * timing follows the data sheets and the packet layout MRPT decodes, so that a simulated sweep
 * can be packed into genuine Velodyne data packets. The Ouster-like sensors (OS64, OS128) fire
 * 1024 columns per revolution, every beam of a column at once, 16 columns per packet.
 *
 * Head azimuth: a sweep starts at sweepStartDeg and turns in spinDirection; by default
 * (Velodyne's convention) it starts at the sensor's +x axis (forward) and turns clockwise seen
 * from above. A laser at elevation e and clockwise azimuth a points along
 * (cos e cos a, -cos e sin a, sin e) in the sensor frame (x forward, y left, z up).
 */
struct LidarModel {
  SensorType type = SensorType::VLP16;
  std::string name;                  ///< "VLP16", "HDL32", "HDL64", "OS64" or "OS128".
  std::vector<double> elevationDeg;  ///< Elevation of each laser, indexed by laser id.
  int64_t firingPeriodNs = 0;        ///< Time between consecutive firings of the same laser.
  int64_t laserTimeOffsetNs = 0;     ///< Delay of laser k within a firing: k * this.
  int firingsPerPacket = 0;  ///< Firings in one data packet (Velodyne: 12 blocks; Ouster: 16).
  double rotationHz = 10.0;  ///< Spin rate; one sweep per revolution.
  double minRange = 0.9;     ///< Closer returns are discarded by the sensor [m].
  double maxRange = 100.0;   ///< No return beyond this range [m].
  /// Azimuth of a sweep's first firing, degrees counter-clockwise from the sensor's +x axis
  /// (the convention of dlo-slam's odometry.sweep_start_azimuth).
  double sweepStartDeg = 0.0;
  /// -1: the head turns clockwise seen from above (Velodyne, Ouster); +1: counter-clockwise.
  int spinDirection = -1;

  int laserCount() const { return static_cast<int>(elevationDeg.size()); }
  /// Azimuth step between consecutive firings [deg].
  double azimuthResolutionDeg() const {
    return 360.0 * rotationHz * static_cast<double>(firingPeriodNs) * 1e-9;
  }
  /// Duration of one data packet [ns].
  int64_t packetPeriodNs() const { return firingPeriodNs * firingsPerPacket; }
  /// True for the sensors whose sweeps fit Velodyne data packets (VLP16, HDL32, HDL64).
  bool velodyne() const {
    return type == SensorType::VLP16 || type == SensorType::HDL32 || type == SensorType::HDL64;
  }
};

/// The model of a sensor type, with the published elevation tables.
LidarModel makeLidarModel(SensorType type);

/// "VLP16", "HDL32", "HDL64", "OS64" or "OS128" (case-insensitive, dashes ignored; also
/// "HDL32E", "HDL64E", "OS1-64", "OS1-128"); nullopt for anything else.
std::optional<SensorType> parseSensorType(const std::string& text);

}  // namespace dlo::sim
