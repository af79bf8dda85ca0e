#include "dlo/slam/sensor_profile.h"

#include <algorithm>
#include <cmath>

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
  e.sensor_height = sensor_pose.translation().z();
  // Elevations in the vehicle frame from the sensor's position: the grid's heights are the
  // vehicle frame's.
  const Eigen::Vector3f origin = sensor_pose.translation().cast<float>();
  std::vector<float> elevation;
  elevation.reserve(points.size());
  for (const Eigen::Vector3f& p : points) {
    const Eigen::Vector3f d = p - origin;
    const float horizontal = d.head<2>().norm();
    if (!(horizontal >= 3.0f && horizontal <= 120.0f) || !std::isfinite(d.z())) continue;
    elevation.push_back(std::atan2(d.z(), horizontal));
  }
  if (elevation.size() >= 1000) {
    const auto at = elevation.begin() + static_cast<std::ptrdiff_t>(0.995 * (elevation.size() - 1));
    std::nth_element(elevation.begin(), at, elevation.end());
    e.top_elevation_deg = static_cast<double>(*at) * 180.0 / M_PI;
  }
  return e;
}

VisibilityCeiling applyVisibilityCeiling(SlamParams& params, const SensorEvidence& e) {
  HeightGridParams& g = params.registration.grid;
  VisibilityCeiling c;
  c.sensor_height = e.sensor_height;
  c.top_elevation_deg = e.top_elevation_deg;
  c.max_z = g.max_z;
  if (!params.odometry.visibility_ceiling || !std::isfinite(e.top_elevation_deg)) return c;
  const double half_width = 0.5 * std::min(g.cols, g.rows) * g.resolution;
  const double top = std::clamp(e.top_elevation_deg, -60.0, 60.0) * M_PI / 180.0;
  // The height seen from every range up to the grid's edge: the sensor's own (plus the margin)
  // for a highest beam at or above the horizontal, what it reaches at the edge for one below.
  const double ceiling =
      e.sensor_height + std::min(params.odometry.ceiling_above_sensor, half_width * std::tan(top));
  if (ceiling < g.max_z && ceiling > g.min_z) {
    g.max_z = ceiling;
    c.max_z = ceiling;
    c.applied = true;
  }
  return c;
}

SensorProfileChoice chooseSensorProfile(const SensorEvidence& e) {
  const auto pick = [](bool sparse, std::string reason) {
    return SensorProfileChoice{sparse ? "sparse" : "dense", std::move(reason), {}};
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

const SensorProfile* builtInSensorProfile(const std::string& profile) {
  for (const SensorProfile& s : sensorProfiles()) {
    if (s.name == profile) return &s;
  }
  if (profile.find('/') == std::string::npos && profile.find(".ini") == std::string::npos) {
    sensorProfile(profile);  // throws, naming the profiles there are
  }
  return nullptr;
}

SlamParams resolveSlamParams(const std::string& profile, const SlamConfigLayers& layers) {
  SlamParams p = applySensorProfile(slamParamTable(), profile, SlamParams());
  if (!layers.config_file.empty()) p = loadSlamParamsFile(layers.config_file, p);
  applySlamParamOverrides(p, layers.sets);
  return p;
}

SensorConfiguration configureForSensor(const std::string& profile, const SlamConfigLayers& layers,
                                       const SensorEvidence& evidence) {
  SensorConfiguration c;
  c.profile = profile == "auto" ? chooseSensorProfile(evidence)
                                : SensorProfileChoice{profile, "--sensor-profile", {}};
  c.params = resolveSlamParams(c.profile.name, layers);
  c.profile.ceiling = applyVisibilityCeiling(c.params, evidence);
  return c;
}

}  // namespace dlo
