#include "dlo/slam/sensor_profile.h"

#include <mrpt/config/CConfigFileMemory.h>

#include "dlo/files/error.h"
#include "dlo/slam/slam_config.h"
#include "sensor_profiles_data.h"

namespace dlo {

namespace {
/// Points per sweep below which a sensor whose rings cannot be counted is taken as sparse: a
/// VLP-16 gives about 29,000, an HDL-32 70,000, an HDL-64 120,000 (10 Hz).
constexpr size_t kSparsePoints = 80000;
}  // namespace

const std::vector<SensorProfile>& sensorProfiles() {
  static const std::vector<SensorProfile> profiles = builtInSensorProfiles();
  return profiles;
}

const SensorProfile& sensorProfile(const std::string& name) {
  std::string names;
  for (const SensorProfile& p : sensorProfiles()) {
    if (p.name == name) return p;
    names += (names.empty() ? "" : ", ") + p.name;
  }
  throw InputError("unknown sensor profile '" + name + "': expected auto, one of " + names +
                   ", or the path of a profile file (config/sensors/*.ini).");
}

SensorEvidence sensorEvidence(const PointCloud& points, int beams,
                              const Eigen::Isometry3d& sensor_pose) {
  SensorEvidence e;
  e.beams = beams;
  e.points = points.size();
  e.rings = estimateRings(points, sensor_pose.inverse().cast<float>());
  return e;
}

SensorProfileChoice chooseSensorProfile(const SensorEvidence& e) {
  const auto pick = [](bool sparse, std::string reason) {
    return SensorProfileChoice{sparse ? "sparse" : "dense", std::move(reason)};
  };
  if (e.beams > 0) {
    return pick(e.beams < kSparseRings,
                "the input's sensor has " + std::to_string(e.beams) + " beams");
  }
  if (e.rings.reliable()) {
    return pick(e.rings.rings < kSparseRings,
                "the first scan shows " + std::to_string(e.rings.rings) + " rings");
  }
  return pick(e.points < kSparsePoints,
              "the first scan has " + std::to_string(e.points) + " points and no clear rings");
}

SlamParams resolveSlamParams(const std::string& profile, const SlamConfigLayers& layers) {
  SlamParams p;
  if (!profile.empty()) {
    bool built_in = false;
    for (const SensorProfile& s : sensorProfiles()) {
      if (s.name != profile) continue;
      mrpt::config::CConfigFileMemory ini(s.ini);
      p = slamParamTable().load(ini, "", p);
      built_in = true;
    }
    if (!built_in) {
      if (profile.find('/') == std::string::npos && profile.find(".ini") == std::string::npos) {
        sensorProfile(profile);  // throws, naming the profiles there are
      }
      p = loadSlamParamsFile(profile, p);
    }
  }
  if (!layers.config_file.empty()) p = loadSlamParamsFile(layers.config_file, p);
  applySlamParamOverrides(p, layers.sets);
  return p;
}

}  // namespace dlo
