/// \file sensor_profile.h
/// \brief Sensor profiles: the settings that depend on the kind of LiDAR (config/sensors/*.ini),
/// chosen from what the input says of its sensor or, failing that, from the rings its first
/// scan shows; and the layering of a run's configuration (profile, then --config, then --set).
#pragma once

#include <string>
#include <vector>

#include "dlo/core/point_cloud.h"
#include "dlo/core/ring_count.h"
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

/// Spinning sensors with fewer rings than this get the "sparse" profile.
constexpr int kSparseRings = 48;

/// What is known of the sensor of a run, from its first non-empty scan.
struct SensorEvidence {
  int beams = 0;       ///< lasers, as the input names them (sensor model, ring channel); 0: unknown
  RingEstimate rings;  ///< the rings the first scan shows (dlo::estimateRings)
  size_t points = 0;   ///< points of the first scan
};

/// The profile a run uses and why.
struct SensorProfileChoice {
  std::string name;  ///< a built-in profile's name, or the path of a profile file
  /// How it was chosen, one phrase for report.json: "the input's sensor has 16 beams", "the
  /// first scan shows 64 rings", "the first scan has 26000 points", "--sensor-profile".
  std::string reason;
};

/// The evidence of one scan: `beams` as the input gives it, the rings of `points` seen from the
/// sensor at `sensor_pose` (vehicle frame).
SensorEvidence sensorEvidence(const PointCloud& points, int beams,
                              const Eigen::Isometry3d& sensor_pose);

/// Picks "sparse" or "dense": from the input's beam count where it is known, else from the rings
/// of the first scan where they are clear (RingEstimate::reliable()), else from its point count
/// (fewer than 80,000 points per sweep: sparse), the weakest evidence.
SensorProfileChoice chooseSensorProfile(const SensorEvidence& evidence);

/// A run's configuration below the profile: an INI file and "section.key=value" overrides.
struct SlamConfigLayers {
  std::string config_file;        ///< empty: none
  std::vector<std::string> sets;  ///< applied after config_file, in order
};

/// The parameters of a run: the defaults, then the profile (a built-in name or an INI file's
/// path; empty: none), then `layers`. Every layer is validated.
/// \throws InputError naming the file or override and the key.
SlamParams resolveSlamParams(const std::string& profile, const SlamConfigLayers& layers);

}  // namespace dlo
