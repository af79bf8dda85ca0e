#include "dlo/slam/localizer_config.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <string>
#include <type_traits>
#include <vector>

#include "dlo/slam/sensor_profile.h"

namespace dlo {

namespace {

constexpr const char* kSection = "localizer";

/// The field `member` of LocalizerParams, a flat struct, in [localizer].
template <typename T>
ParamField<LocalizerParams> field(const char* key, T LocalizerParams::*member, const char* doc) {
  static_assert(std::is_same_v<T, int> || std::is_same_v<T, double> || std::is_same_v<T, bool>,
                "int, double or bool parameters");
  return ParamField<LocalizerParams>{
      kSection,
      key,
      doc,
      !std::is_same_v<T, double>,
      [member](const LocalizerParams& p) { return static_cast<double>(p.*member); },
      [member](LocalizerParams& p, double v) {
        if constexpr (std::is_same_v<T, bool>) {
          p.*member = v != 0.0;
        } else {
          p.*member = static_cast<T>(v);
        }
      },
      std::is_same_v<T, bool> ? booleanNames() : std::vector<NamedValue>{}};
}

std::vector<ParamField<LocalizerParams>> fields() {
  using P = LocalizerParams;
  return {
      field("cells", &P::cells,
            "cells per side of the registration grid (the scan's and the map window's), at the "
            "height map's resolution (0.2 m from dlo-slam: 300 cells are 60 m across)"),
      field("rebuild_distance", &P::rebuild_distance,
            "metres; the map window is cut again around the vehicle when it is this far from the "
            "window's centre"),
      field("min_inliers", &P::min_inliers,
            "fraction of the scan's selected cells that must find the map for a registration "
            "to be believed (the scan localised)"),
      field("rms_ratio", &P::rms_ratio,
            ">= 1; a registration whose RMS height error is above this times the median of the "
            "last localised scans' is not believed (a wrong basin, or surroundings that changed "
            "since the map, fit worse than the drive usually does)"),
      field("max_rms", &P::max_rms,
            "metres; RMS height error above which a registration is never believed (the only "
            "bound before the median exists, e.g. from --init)"),
      field("max_correction", &P::max_correction,
            "metres; a registration that moves the pose farther than this from its prediction "
            "has found another basin and is not believed"),
      field("tracking_basin", &P::tracking_basin,
            "metres; tracking registers on the pyramid's levels up to this cell size (a search "
            "uses every level, up to 1.6 m): coarser levels only add basins to fall into"),
      field("lost_after", &P::lost_after,
            "scans in a row not localised after which the vehicle is lost and the whole map is "
            "searched again"),
      field("search_every", &P::search_every,
            "while lost, a global search runs at most once every this many scans"),
      field("search_spacing", &P::search_spacing,
            "metres; the global search starts at the map's keyframes at least this far apart"),
      field("search_yaw_step_deg", &P::search_yaw_step_deg,
            "degrees between the headings the global search starts from at each keyframe"),
      field("search_contrast", &P::search_contrast,
            ">= 1; the best place a search finds must cost at most the median place's divided "
            "by this (refuses scans that fit everywhere alike)"),
      field("ambiguity_ratio", &P::ambiguity_ratio,
            ">= 1; every other distinct place must cost at least this times the best's, else "
            "the search found nothing (parallel streets, a town the map does not hold)"),
      field("bridge_only", &P::bridge_only,
            "true: once the map has localised four scans in a row, the odometry stops and the "
            "localised poses' velocity predicts and deskews the next scan; a scan it does not "
            "carry is registered again from an odometry started on the previous scan, which then "
            "bridges (a half to a third of the time per scan); false: the odometry runs beside "
            "every scan"),
  };
}

bool isLocalizerAssignment(const std::string& a) {
  const auto dot = a.find('.');
  return dot != std::string::npos && param_text::trim(a.substr(0, dot)) == kSection;
}

}  // namespace

const ParamTable<LocalizerParams>& localizerParamTable() {
  static const ParamTable<LocalizerParams> t(fields(),
                                             [](const LocalizerParams& p) { return p.validate(); });
  return t;
}

void splitLocalizerOverrides(const std::vector<std::string>& assignments,
                             std::vector<std::string>& slam, std::vector<std::string>& localizer) {
  for (const std::string& a : assignments)
    (isLocalizerAssignment(a) ? localizer : slam).push_back(a);
}

LocalizerParams resolveLocalizerParams(const std::string& profile, const std::string& config_file,
                                       const std::vector<std::string>& sets) {
  LocalizerParams p = applySensorProfile(localizerParamTable(), profile, LocalizerParams());
  if (!config_file.empty()) p = localizerParamTable().loadFile(config_file, "", p);
  std::vector<std::string> slam, localizer;
  splitLocalizerOverrides(sets, slam, localizer);
  localizerParamTable().applyOverrides(p, localizer);
  return p;
}

std::vector<std::string> localizerProfileKeys() {
  std::vector<std::string> keys;
  for (const ParamField<LocalizerParams>& f : localizerParamTable().fields()) {
    for (const SensorProfile& profile : sensorProfiles()) {
      mrpt::config::CConfigFileMemory ini(profile.ini);
      if (!ini.read_string(kSection, f.key, "").empty() &&
          std::find(keys.begin(), keys.end(), f.name()) == keys.end()) {
        keys.push_back(f.name());
      }
    }
  }
  return keys;
}

std::string localizerParamsToIni(const LocalizerParams& params) {
  return localizerParamTable().toIni(params, "");
}

std::string localizerConfigFileText() {
  return param_text::comment(
             "dlo-localize parameters (MRPT INI), generated from the parameter table "
             "(docs/parameters.md lists the same). [localizer] sets how scans are registered "
             "against the map and when they are believed; the same file may also hold dlo-slam's "
             "sections ([grid] [selection] [solver] [odometry], config/dlo-slam.ini), which the "
             "odometry and the registrations use. Use with: dlo-localize --config "
             "config/dlo-localize.ini, and override single keys with --set "
             "localizer.key=value; dlo-localize --dump-config prints the effective "
             "configuration. Every key is optional: a missing key keeps the default shown here. "
             "A value out of range is rejected naming section.key and the range.") +
         ";\n" +
         param_text::comment(
             "The keys that depend on the kind of sensor are set by the sensor profile, "
             "config/sensors/dense.ini or sparse.ini, which dlo-localize picks from the input "
             "(--sensor-profile); they are commented out below, with the dense profile's "
             "values.") +
         "\n" +
         localizerParamTable().toIni(LocalizerParams(), "", localizerProfileKeys(),
                                     "(sensor profile)");
}

}  // namespace dlo
