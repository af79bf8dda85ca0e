// Geometry and timing of the simulated rotating LiDARs (Velodyne VLP-16, HDL-32E, HDL-64E).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dlo::sim {

/// The sensors the simulator knows.
enum class SensorType { VLP16, HDL32, HDL64 };

/**
 * A spinning multi-beam LiDAR: elevation table, firing timing and range limits.
 *
 * Timing follows the Velodyne data sheets and the packet layout MRPT decodes, so a simulated
 * sweep can be packed into genuine Velodyne data packets: a "firing" fires every laser once
 * (laser k at firing time + k * laserTimeOffsetNs), firings repeat every firingPeriodNs while
 * the head spins clockwise (seen from above) at rotationHz. Azimuth 0 is the sensor's +x axis
 * (forward); a laser at elevation e and azimuth a points along
 * (cos e cos a, -cos e sin a, sin e) in the sensor frame (x forward, y left, z up).
 */
struct LidarModel {
  SensorType type = SensorType::VLP16;
  std::string name;                  ///< "VLP16", "HDL32" or "HDL64".
  std::vector<double> elevationDeg;  ///< Elevation of each laser, indexed by laser id.
  int64_t firingPeriodNs = 0;        ///< Time between consecutive firings of the same laser.
  int64_t laserTimeOffsetNs = 0;     ///< Delay of laser k within a firing: k * this.
  int firingsPerPacket = 0;          ///< Firings in one Velodyne data packet (12 blocks).
  double rotationHz = 10.0;          ///< Spin rate; one sweep per revolution.
  double minRange = 0.9;             ///< Closer returns are discarded by the sensor [m].
  double maxRange = 100.0;           ///< No return beyond this range [m].

  int laserCount() const { return static_cast<int>(elevationDeg.size()); }
  /// Azimuth step between consecutive firings [deg].
  double azimuthResolutionDeg() const {
    return 360.0 * rotationHz * static_cast<double>(firingPeriodNs) * 1e-9;
  }
  /// Duration of one data packet [ns].
  int64_t packetPeriodNs() const { return firingPeriodNs * firingsPerPacket; }
};

/// The model of a sensor type, with the published elevation tables.
LidarModel makeLidarModel(SensorType type);

/// "VLP16", "HDL32" or "HDL64" (case-insensitive, dashes ignored); nullopt for anything else.
std::optional<SensorType> parseSensorType(const std::string& text);

}  // namespace dlo::sim
