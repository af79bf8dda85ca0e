#include "dlo/slam/slam_config.h"

#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>

#include "dlo/mrpt/dlo_config.h"
#include "dlo/slam/localizer_config.h"
#include "dlo/slam/sensor_profile.h"

namespace dlo {

namespace {

std::vector<ParamField<SlamParams>> fields() {
  using S = SlamParams;
  using O = OdometryParams;
  using L = LoopParams;
  std::vector<ParamField<S>> table;
  for (const ParamField<DloParams>& f : dloParamFields()) {
    table.push_back(liftField(f, &S::registration));
  }
  const std::vector<ParamField<S>> own = {
      paramField("odometry", "reference", &S::odometry, &O::reference,
                 "what each scan is registered against: previous (the previous scan, the "
                 "paper's frame-to-frame), keyframe (the last keyframe), keyframe_map (a local "
                 "map of recent keyframes) or scan_map (a world-fixed local height map of the "
                 "last registered scans, updated every scan)",
                 {{"previous", 0}, {"keyframe", 1}, {"keyframe_map", 2}, {"scan_map", 3}}),
      paramField("odometry", "levelling", &S::odometry, &O::levelling,
                 "true: z, roll and pitch of each scan measured from its ground laid on the "
                 "reference's ground, x, y and yaw registered by solver.dof = 3 (a 3D "
                 "trajectory); false: z, roll and pitch kept as predicted (the paper's planar "
                 "3-DoF); ignored with solver.dof = 6, which solves all six jointly",
                 booleanNames()),
      paramField("odometry", "visibility_ceiling", &S::odometry, &O::visibility_ceiling,
                 "true: heights above what the sensor sees from every range on the grid are "
                 "left out (grid.max_z lowered to the sensor's height + ceiling_above_sensor, or "
                 "to what its highest beam reaches at the grid's edge where that is lower, read "
                 "off the first scan), so that a wall has the same mean height from every range; "
                 "false: grid.max_z as set (the sparse profile)",
                 booleanNames()),
      paramField("odometry", "ceiling_above_sensor", &S::odometry, &O::ceiling_above_sensor,
                 "metres; with visibility_ceiling, the band kept above the sensor's height: a "
                 "beam at or above the horizontal sees a wall up to the sensor's height from "
                 "any range, higher only from far enough away; the band trades what near walls "
                 "lose against ground rising ahead over a crest"),
      paramField("odometry", "local_map_keyframes", &S::odometry, &O::local_map_keyframes,
                 "the most recent keyframes fused into the local map (reference = "
                 "keyframe_map), at most; more of them dilute the pattern of rings that travels "
                 "with the sensor, which keyframes taken close together (turning on the spot) "
                 "share"),
      paramField("odometry", "local_map_extent", &S::odometry, &O::local_map_extent,
                 "metres; a keyframe farther than this from the newest one leaves the local map "
                 "(reference = keyframe_map) even before local_map_keyframes newer ones replace "
                 "it: older keyframes carry more of the odometry's drift; 0: no limit"),
      paramField("odometry", "local_map_scans", &S::odometry, &O::local_map_scans,
                 "registered scans in the local height map (reference = scan_map)"),
      paramField("odometry", "local_map_spacing", &S::odometry, &O::local_map_spacing,
                 "metres; a registered scan joins the local height map (reference = scan_map) only "
                 "this far from the last scan that joined it, and a keyframe closer than this to "
                 "the newest one of the keyframe map (reference = keyframe_map) replaces it, so "
                 "that the map's views are spread out and the pattern of rings that travels "
                 "with the sensor cancels out; 0: every scan or keyframe joins"),
      paramField("odometry", "max_prior_deviation", &S::odometry, &O::max_prior_deviation,
                 "metres; a registration farther than this from the constant-velocity "
                 "prediction (rotations counted at solver.rotation_scale) is decided by the "
                 "scan: deskewed with the motion it measured and registered from other starts, "
                 "the best fit wins if it beats the prediction's by a margin growing with its "
                 "distance from the prediction, or from the last motion continued or the turn "
                 "stopped where nearer (README); the bound grows by as much with each consecutive "
                 "scan where the prediction was kept (a quarter as much for rotations); 0: off"),
      paramField("odometry", "recheck_worse_fits", &S::odometry, &O::recheck_worse_fits,
                 "true: a registration more than a quarter of max_prior_deviation from the "
                 "prediction that fits the scan worse than the prediction is decided by the "
                 "scan as one beyond max_prior_deviation is (the sparse profile); false: only "
                 "those beyond it",
                 booleanNames()),
      paramField("odometry", "max_acceleration", &S::odometry, &O::max_acceleration,
                 "m/s^2; the speed carried to the next scan changes by at most this per "
                 "second; 0: no limit"),
      paramField("odometry", "max_yaw_acceleration", &S::odometry, &O::max_yaw_acceleration,
                 "deg/s^2; likewise for the yaw rate, unless the scan disagreed with the "
                 "prediction and its registration halved the prediction's cost; 0: no limit"),
      paramField("odometry", "yaw_rate_decay", &S::odometry, &O::yaw_rate_decay,
                 "seconds; a yaw rate that the scans do not measure (an open road, a covered "
                 "sensor) returns to zero with this time constant instead of being carried on; "
                 "0: carried unchanged"),
      paramField("odometry", "max_rejected_scans", &S::odometry, &O::max_rejected_scans,
                 "consecutive scans where the prediction was kept after which registrations are "
                 "believed again"),
      paramField("odometry", "max_speed", &S::odometry, &O::max_speed,
                 "m/s; the fastest the vehicle is expected to move: until the velocity along a "
                 "direction is measured, a registration that cannot observe that direction "
                 "searches for structure along it up to this speed; 0: never search"),
      paramField("odometry", "max_yaw_rate", &S::odometry, &O::max_yaw_rate,
                 "deg/s; the fastest the vehicle is expected to turn: each scan's fit is "
                 "compared at the coarsest level over the headings this allows, and a scan "
                 "that fits better at another is registered from there too (a turn "
                 "begun faster than a registration's basin reaches); 0: never search"),
      paramField("odometry", "keyframe_distance", &S::odometry, &O::keyframe_distance,
                 "metres travelled since the last keyframe that make a new one"),
      paramField("odometry", "keyframe_angle", &S::odometry, &O::keyframe_angle,
                 "degrees turned since the last keyframe that make a new one"),
      paramField(
          "odometry", "keyframe_max_rms", &S::odometry, &O::keyframe_max_rms,
          "0 (off) or the registration RMS height error (m) above which the scan "
          "becomes a keyframe (reference keyframe or keyframe_map only: their reference is made of "
          "keyframes)"),
      paramField("odometry", "keyframe_rms_ratio", &S::odometry, &O::keyframe_rms_ratio,
                 "0 (off) or >= 1: a fit above keyframe_max_rms makes a keyframe only if it is "
                 "also this many times worse than the first fits against the last 5 keyframes"),
      paramField("odometry", "keyframe_voxel", &S::odometry, &O::keyframe_voxel,
                 "metres; decimation of keyframe clouds for the local map"),
      paramField("odometry", "map_voxel", &S::odometry, &O::map_voxel,
                 "metres; decimation of keyframe clouds kept for loop closure and the map"),
      paramField("odometry", "map_range", &S::odometry, &O::map_range,
                 "metres; keyframe points farther than this from the vehicle are not kept"),
      paramField("odometry", "deskew", &S::odometry, &O::deskew,
                 "true: undo motion distortion (with the points' times, measured or "
                 "estimated); false: off",
                 booleanNames()),
      paramField("odometry", "estimate_times", &S::odometry, &O::estimate_times,
                 "true: scans without per-point times (KITTI .bin, PLY, point-cloud "
                 "observations) get them estimated from the points' azimuths and are deskewed; "
                 "false: used as they are",
                 booleanNames()),
      paramField("odometry", "sweep_period", &S::odometry, &O::sweep_period,
                 "seconds per revolution of the sensor (estimated times); 0: read off the "
                 "scans' timestamps (their mean interval, dropped scans and gaps left out)"),
      paramField("odometry", "sweep_direction", &S::odometry, &O::sweep_direction,
                 "-1: the sensor spins clockwise seen from above (Velodyne, Ouster, Hesai); 1: "
                 "counter-clockwise; used when the point order does not reveal it"),
      paramField("odometry", "sweep_start_azimuth", &S::odometry, &O::sweep_start_azimuth,
                 "degrees counter-clockwise from forward where a sweep begins (KITTI: 180); "
                 "used when the point order does not reveal it"),
      paramField("odometry", "sweep_stamp", &S::odometry, &O::sweep_stamp,
                 "where in its sweep a scan without per-point times is stamped: 0 first point, "
                 "0.5 middle (KITTI), 1 last point"),
      paramField("odometry", "resident_keyframes", &S::odometry, &O::resident_keyframes,
                 "keyframe clouds kept in memory; older ones wait in a temporary file until "
                 "loop closure or export reads them (flat memory on long runs); 0: all in memory"),
      paramField("loop", "enabled", &S::loop, &L::enabled,
                 "true: search and close loops; false: off", booleanNames()),
      paramField("loop", "search_radius", &S::loop, &L::search_radius,
                 "metres between keyframe positions for a loop candidate"),
      paramField("loop", "min_path", &S::loop, &L::min_path,
                 "metres travelled between the two keyframes of a candidate, at least"),
      paramField("loop", "retry_distance", &S::loop, &L::retry_distance,
                 "metres travelled after a search that closed no loop before the next one; 0: "
                 "search at every keyframe"),
      paramField("loop", "resolution", &S::loop, &L::resolution,
                 "metres per cell of the verification grid"),
      paramField("loop", "window", &S::loop, &L::window, "metres; side of the verification grid"),
      paramField("loop", "max_rms", &S::loop, &L::max_rms,
                 "verification RMS height error (m) above which a candidate is rejected"),
      paramField("loop", "min_inliers", &S::loop, &L::min_inliers,
                 "fraction of the selected cells that must keep a residual"),
      paramField("loop", "max_correction", &S::loop, &L::max_correction,
                 "metres between the guess and the verified pose, at most"),
      paramField("loop", "max_disagreement", &S::loop, &L::max_disagreement,
                 "metres; with confirm, the two loops must put the vehicle within this of each "
                 "other"),
      paramField("loop", "min_sigma_xy", &S::loop, &L::min_sigma_xy,
                 "metres; floor of the standard deviations of graph edges (x, y, z)"),
      paramField("loop", "min_sigma_angle", &S::loop, &L::min_sigma_angle,
                 "degrees; floor of the standard deviations of graph edges (angles)"),
      paramField("loop", "submap_keyframes", &S::loop, &L::submap_keyframes,
                 "keyframes put together on each side of a verification (the keyframe and its "
                 "neighbours along the drive); 1: the keyframe alone"),
      paramField(
          "loop", "confirm", &S::loop, &L::confirm,
          "true: the first loop of a revisit is added only once a later keyframe's "
          "search finds a loop in the same basin (within max_disagreement and 2.5 deg); false: "
          "one verification suffices",
          booleanNames()),
  };
  table.insert(table.end(), own.begin(), own.end());
  return table;
}

/// `text` with its pipes escaped for a Markdown table cell.
std::string markdownCell(std::string text) {
  for (size_t at = 0; (at = text.find('|', at)) != std::string::npos; at += 2)
    text.replace(at, 1, "\\|");
  return text;
}

}  // namespace

const ParamTable<SlamParams>& slamParamTable() {
  static const ParamTable<SlamParams> t(fields(), [](const SlamParams& p) { return p.validate(); });
  return t;
}

SlamParams loadSlamParamsFile(const std::string& path, const SlamParams& defaults) {
  return slamParamTable().loadFile(path, "", defaults);
}

void applySlamParamOverrides(SlamParams& params, const std::vector<std::string>& assignments) {
  slamParamTable().applyOverrides(params, assignments);
}

std::string slamParamsToIni(const SlamParams& params) {
  return slamParamTable().toIni(params, "");
}

std::vector<std::string> sensorProfileKeys() {
  std::vector<std::string> keys;
  for (const SensorProfile& profile : sensorProfiles()) {
    mrpt::config::CConfigFileMemory ini(profile.ini);
    std::vector<std::string> sections;
    ini.getAllSections(sections);
    for (const std::string& section : sections) {
      std::vector<std::string> section_keys;
      ini.getAllKeys(section, section_keys);
      for (const std::string& key : section_keys) {
        const std::string name = section + "." + key;
        if (std::find(keys.begin(), keys.end(), name) == keys.end()) keys.push_back(name);
      }
    }
  }
  // In the order of the table, as the files list them.
  std::vector<std::string> ordered;
  for (const ParamField<SlamParams>& f : slamParamTable().fields()) {
    if (std::find(keys.begin(), keys.end(), f.name()) != keys.end()) ordered.push_back(f.name());
  }
  return ordered;
}

std::string slamConfigFileText() {
  const std::vector<std::string> profile_keys = sensorProfileKeys();
  std::string listed;
  for (size_t i = 0; i < profile_keys.size(); ++i) {
    listed += (i == 0 ? "" : i + 1 == profile_keys.size() ? " and " : ", ") + profile_keys[i];
  }
  return param_text::comment(
             "dlo-slam parameters (MRPT INI), generated from the parameter tables "
             "(docs/parameters.md lists the same). [grid] [selection] [solver] configure each "
             "registration (as in config/dlo.ini); [odometry] and [loop] the pipeline around it. "
             "Use with: dlo-slam --config config/dlo-slam.ini, and override single keys with "
             "--set section.key=value; dlo-slam --dump-config prints the effective "
             "configuration. Every key is optional: a missing key keeps the default shown here. "
             "A value out of range is rejected naming section.key and the range.") +
         ";\n" +
         param_text::comment(
             "The keys that depend on the kind of sensor (" + listed +
             ") are set by the sensor profile, config/sensors/dense.ini or sparse.ini, which "
             "dlo-slam picks from the input (--sensor-profile); they are commented out below, "
             "with the dense profile's values: uncomment one to use it with every sensor. This "
             "file and --set apply on top of the profile; report.json names the profile and "
             "shows the configuration used.") +
         "\n" + slamParamTable().toIni(SlamParams(), "", profile_keys, "(sensor profile)");
}

std::string parameterReferenceMarkdown() {
  const ParamTable<SlamParams>& table = slamParamTable();
  std::vector<std::pair<std::string, SlamParams>> profiles;
  for (const SensorProfile& p : sensorProfiles())
    profiles.emplace_back(p.name, resolveSlamParams(p.name, {}));
  const std::vector<std::string> profile_keys = sensorProfileKeys();
  std::string out =
      "# Parameters\n\n"
      "Generated from the parameter tables (`libs/mrpt/src/dlo_config.cpp`, "
      "`libs/slam/src/slam_config.cpp`), like the comments of `config/dlo.ini` and "
      "`config/dlo-slam.ini` and `dlo-slam --dump-config`; a test fails when one of them "
      "differs. `dlo-register` and `CDirectHeightAligner` read [grid] [selection] [solver]; "
      "`dlo-slam` all five sections; `dlo-localize` these and [localizer] "
      "(`libs/slam/src/localizer_config.cpp`, `config/dlo-localize.ini`). Set a key in an INI "
      "file (`--config`) or with "
      "`--set section.key=value`. Keys marked *profile* are set by the sensor profile "
      "(`config/sensors/`), which dlo-slam picks from the input.\n";
  std::string current;
  for (const ParamField<SlamParams>& f : table.fields()) {
    if (f.section != current) {
      current = f.section;
      out += "\n## [" + current + "]\n\n| key | default | description |\n|---|---|---|\n";
    }
    std::string value = "`" + ParamTable<SlamParams>::text(f, SlamParams()) + "`";
    if (std::find(profile_keys.begin(), profile_keys.end(), f.name()) != profile_keys.end()) {
      value = "*profile*:";
      for (const auto& [name, params] : profiles)
        value += " " + name + " `" + ParamTable<SlamParams>::text(f, params) + "`";
    }
    out += "| `" + f.key + "` | " + value + " | " + markdownCell(f.doc) + " |\n";
  }
  out += "\n## [localizer]\n\n| key | default | description |\n|---|---|---|\n";
  const std::vector<std::string> localizer_keys = localizerProfileKeys();
  for (const ParamField<LocalizerParams>& f : localizerParamTable().fields()) {
    std::string value = "`" + ParamTable<LocalizerParams>::text(f, LocalizerParams()) + "`";
    if (std::find(localizer_keys.begin(), localizer_keys.end(), f.name()) != localizer_keys.end()) {
      value = "*profile*:";
      for (const SensorProfile& p : sensorProfiles()) {
        value += " " + p.name + " `" +
                 ParamTable<LocalizerParams>::text(f, resolveLocalizerParams(p.name, "", {})) + "`";
      }
    }
    out += "| `" + f.key + "` | " + value + " | " + markdownCell(f.doc) + " |\n";
  }
  return out;
}

}  // namespace dlo
