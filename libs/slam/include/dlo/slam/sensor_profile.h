/// \file sensor_profile.h
/// \brief Sensor profiles: the settings that depend on the kind of LiDAR (config/sensors/*.ini),
/// chosen from what the input says of its sensor or, failing that, from the rings its first
/// scan shows; and the layering of a run's configuration (profile, then --config, then --set).
#pragma once

#include <mrpt/config/CConfigFileMemory.h>

#include <limits>
#include <string>
#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/core/ring_count.h"
#include "dlo/mrpt/param_table.h"
#include "dlo/slam/slam_params.h"

namespace dlo {

/// A built-in profile: config/sensors/NAME.ini, compiled in.
struct SensorProfile {
  std::string name;  ///< "dense", "sparse"
  std::string ini;   ///< the file's text: the keys it sets, commented
};

/// The built-in profiles, in the order of config/sensors/.
const std::vector<SensorProfile>& sensorProfiles();

/// The profile named `name`. \throws InputError listing the names when there is none.
const SensorProfile& sensorProfile(const std::string& name);

/// The built-in profile `profile` names, or nullptr when `profile` is the path of a profile file
/// (it holds a '/' or ".ini"). \throws InputError listing the names for any other unknown name.
const SensorProfile* builtInSensorProfile(const std::string& profile);

/// `params` with the sections of `table` that the sensor profile `profile` sets (a built-in
/// name or a profile file's path; empty: none) applied, validated. Every parameter struct a
/// profile configures (SlamParams, LocalizerParams) is layered through this.
/// \throws InputError naming the file or profile and the key.
template <typename P>
P applySensorProfile(const ParamTable<P>& table, const std::string& profile, const P& params) {
  if (profile.empty()) return params;
  if (const SensorProfile* s = builtInSensorProfile(profile)) {
    const mrpt::config::CConfigFileMemory ini(s->ini);
    return table.load(ini, "", params);
  }
  return table.loadFile(profile, "", params);
}

/// Spinning sensors with fewer rings than this get the "sparse" profile.
constexpr int kSparseRings = 48;

/// What is known of the sensor of a run, from its first non-empty scan.
struct SensorEvidence {
  int beams = 0;       ///< lasers, as the input names them (sensor model, ring channel); 0: unknown
  RingEstimate rings;  ///< the rings the first scan shows (dlo::estimateRings)
  size_t points = 0;   ///< points of the first scan
  /// Height of the sensor in the vehicle frame (the z of its pose), metres.
  double sensor_height = 0.0;
  /// The elevation of the sensor's highest beam, degrees above the horizontal, seen from the
  /// sensor: the 99.5th percentile of the points 3 to 120 m away horizontally; NaN with fewer
  /// than 1000 of them.
  double top_elevation_deg = std::numeric_limits<double>::quiet_NaN();
};

/// The height band a run's grids keep (OdometryParams::visibility_ceiling).
struct VisibilityCeiling {
  bool applied = false;  ///< grid.max_z was lowered
  double max_z = 0.0;    ///< grid.max_z in use, metres (vehicle frame)
  double sensor_height = 0.0;
  double top_elevation_deg = std::numeric_limits<double>::quiet_NaN();
};

/// The profile a run uses and why.
struct SensorProfileChoice {
  std::string name;  ///< a built-in profile's name, or the path of a profile file
  /// How it was chosen, one phrase for report.json: "the input's sensor has 16 beams", "the
  /// first scan shows 64 rings", "the first scan has 26000 points", "--sensor-profile".
  std::string reason;
  VisibilityCeiling ceiling;  ///< as applyVisibilityCeiling() left it
};

/// The evidence of one scan: `beams` as the input gives it, the rings of `points` seen from the
/// sensor at `sensor_pose` (vehicle frame).
SensorEvidence sensorEvidence(const PointCloud& points, int beams,
                              const Eigen::Isometry3d& sensor_pose);

/// Picks "sparse" or "dense": from the input's beam count where it is known, else from the rings
/// of the first scan where they are clear (RingEstimate::reliable()), else from its point count
/// (fewer than 80,000 points per sweep: sparse), the weakest evidence.
SensorProfileChoice chooseSensorProfile(const SensorEvidence& evidence);

/// With params.odometry.visibility_ceiling, lowers params.registration.grid.max_z to the
/// height the sensor sees from every range up to the grid's edge: sensor_height +
/// min(odometry.ceiling_above_sensor, (half the grid's narrower side) x tan(top_elevation_deg)),
/// so that every cell's height band is seen whole from anywhere on the grid (a simulated HDL-64
/// or Ouster-like sensor 1.8 m up: 2.5 m above the ground). No-op when the evidence has no top
/// elevation or the ceiling is off (the sparse profile).
VisibilityCeiling applyVisibilityCeiling(SlamParams& params, const SensorEvidence& evidence);

/// A run's configuration below the profile: an INI file and "section.key=value" overrides.
struct SlamConfigLayers {
  std::string config_file;        ///< empty: none
  std::vector<std::string> sets;  ///< applied after config_file, in order
};

/// The parameters of a run: the defaults, then the profile (a built-in name or an INI file's
/// path; empty: none), then `layers`. Every layer is validated.
/// \throws InputError naming the file or override and the key.
SlamParams resolveSlamParams(const std::string& profile, const SlamConfigLayers& layers);

/// A run's parameters and the profile they came from (configureForSensor()).
struct SensorConfiguration {
  SlamParams params;
  SensorProfileChoice profile;
};

/// The parameters of a run as dlo-slam sets them from its first scan: the profile (`profile`
/// "auto": the one chooseSensorProfile() picks from `evidence`; otherwise a built-in name or a
/// profile file's path, chosen by --sensor-profile), then `layers` (resolveSlamParams()), then
/// the visibility ceiling read off `evidence` (applyVisibilityCeiling()).
/// \throws InputError naming the file or override and the key.
SensorConfiguration configureForSensor(const std::string& profile, const SlamConfigLayers& layers,
                                       const SensorEvidence& evidence);

}  // namespace dlo
