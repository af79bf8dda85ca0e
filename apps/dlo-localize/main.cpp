// dlo-localize: localises a drive on a map that dlo-slam made. The localisation lives in
// libs/slam (dlo::Localizer); this file parses the command line, streams the input and reports.
#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/app/scan_input_options.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/files/atomic_file.h"
#include "dlo/files/error.h"
#include "dlo/metrics/error_statistics.h"
#include "dlo/metrics/timestamp_matching.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/open_scan_source.h"
#include "dlo/slam/localizer.h"
#include "dlo/slam/localizer_config.h"
#include "dlo/slam/sensor_profile.h"
#include "dlo/slam/slam_config.h"

namespace {

constexpr const char* kDescription =
    "Localises the LiDAR scans of IN on a map that dlo-slam made (its output folder MAP): with no "
    "--init, a search over the whole map finds the start; then every scan is registered against "
    "the map around its predicted pose, and a search runs again whenever the vehicle is lost.";

constexpr const char* kFooter = R"(Outputs in DIR (each file atomically):
  trajectory.tum     the localised scans' poses in the map's frame (scans not localised are left
                     out)
  localization.csv   one line per scan: time, localised, searched, found, confidence (0-1), RMS
                     height error, inlier fraction, x, y, z, yaw (deg), ms, odometry (whether the
                     odometry ran: localizer.bridge_only)
  report.json        ms per scan (median, p95), fraction of scans localised, re-localisations,
                     scans and seconds to the first fix, scans the odometry ran on, and with --gt
                     the position error
  localization.png   the map from above with the path: green localised, red predicted

Input: as dlo-slam's (a rawlog, a Velodyne .pcap with --model, or a KITTI folder).
SIGINT or SIGTERM stops after the current scan and writes the outputs (exit status 3).
Exit status: 0 on success, 1 for a bad input file or parameter, 2 for a command-line error,
3 when interrupted; errors are one line on stderr starting with "dlo-localize: ".)";

std::atomic<bool> g_stop{false};
void onSignal(int) {
  g_stop = true;
}

using dlo::UsageError;
using Json = nlohmann::ordered_json;

struct Arguments {
  std::string map, input, out, init, gt, config, sensor_profile = "auto";
  std::vector<std::string> sets;
  dlo::ScanInputOptions scans;
  bool quiet = false, dump_config = false;
  std::optional<Eigen::Isometry3d> initial_pose;
};

std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-localize", kDescription);
  cl.text("--map", a.map,
          "a dlo-slam output folder (its heightmap.bin, heightmap_centroids.bin and "
          "map.simplemap are read); required unless --dump-config")
      .valueName("MAP");
  cl.text("--input", a.input,
          "the drive to localise: a rawlog, a Velodyne .pcap or a KITTI folder; required unless "
          "--dump-config")
      .valueName("IN");
  cl.text("--out", a.out, "output folder (created if needed); required unless --dump-config")
      .valueName("DIR");
  cl.text("--init", a.init,
          "the first scan's pose in the map's frame, metres and degrees; without it the whole "
          "map is searched")
      .valueName("\"x y yaw\"");
  cl.text("--gt", a.gt, "ground truth in the map's frame (TUM or KITTI), for report.json's error")
      .valueName("FILE");
  cl.text("--config", a.config,
          "MRPT INI: [localizer] (see config/dlo-localize.ini) and dlo-slam's sections for the "
          "odometry and the registrations (config/dlo-slam.ini)")
      .valueName("FILE");
  cl.repeatable("--set", a.sets, "overrides one parameter after --config; may be repeated")
      .valueName("section.key=value");
  cl.text("--sensor-profile", a.sensor_profile, "as dlo-slam's")
      .valueName("auto|dense|sparse|FILE");
  dlo::declareScanInputOptions(cl, a.scans, dlo::kScanAll);
  cl.flag("--quiet", a.quiet, "no progress bar");
  cl.flag("--dump-config", a.dump_config,
          "print the effective configuration as INI ([localizer], then dlo-slam's sections; "
          "with auto, the dense profile's) and exit");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (a.dump_config) return a;
  if (a.map.empty()) throw UsageError{"--map is required (see --help)."};
  if (a.input.empty()) throw UsageError{"--input is required (see --help)."};
  if (a.out.empty()) throw UsageError{"--out is required (see --help)."};
  dlo::checkScanInputOptions(a.scans);
  if (!a.init.empty()) {
    std::istringstream in(a.init);
    double x = 0.0, y = 0.0, yaw = 0.0;
    std::string rest;
    if (!(in >> x >> y >> yaw) || (in >> rest) || !std::isfinite(x) || !std::isfinite(y) ||
        !std::isfinite(yaw)) {
      throw UsageError{"--init takes three numbers, \"x y yaw\" (metres, metres, degrees); got '" +
                       a.init + "'."};
    }
    a.initial_pose = dlo::poseFromXYZYPR(x, y, 0.0, yaw * M_PI / 180.0, 0.0, 0.0);
  }
  return a;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5))];
}

/// The report, from the steps of the run.
Json report(const Arguments& args, const dlo::Localizer& localizer,
            const std::vector<dlo::LocalizationStep>& steps, const std::string& profile,
            const dlo::SlamParams& params,
            const std::optional<dlo::metrics::Trajectory>& ground_truth, bool interrupted,
            const std::string& input_error) {
  std::vector<double> ms;
  size_t localised = 0, searches = 0, relocalisations = 0, odometry = 0;
  long first_fix = -1;
  for (size_t i = 0; i < steps.size(); ++i) {
    const dlo::LocalizationStep& s = steps[i];
    ms.push_back(s.ms);
    localised += s.localised;
    odometry += s.odometry;
    searches += s.searched;
    if (s.found && first_fix >= 0) ++relocalisations;
    if (s.localised && first_fix < 0) first_fix = static_cast<long>(i);
  }
  Json j;
  j["map"] = args.map;
  j["map_keyframes"] = localizer.map().size();
  // Whether the map's heights were moved to their cells' centres (docs/apps.md, dlo-localize):
  // false with the sparse profile, or for a map made before dlo-slam wrote its centroids.
  j["map_heights_at_centres"] = localizer.map().heights_at_centres;
  j["input"] = args.input;
  j["sensor_profile"] = profile;
  j["scans"] = steps.size();
  j["ms_per_scan"] = {{"median", percentile(ms, 0.5)}, {"p95", percentile(ms, 0.95)}};
  j["localised_fraction"] = steps.empty() ? 0.0 : static_cast<double>(localised) / steps.size();
  j["localised_scans"] = localised;
  j["searches"] = searches;
  j["relocalisations"] = relocalisations;
  j["odometry_scans"] = odometry;
  if (first_fix >= 0) {
    j["first_fix"] = {{"scan", first_fix},
                      {"seconds", steps[first_fix].time - steps.front().time},
                      {"from_initial_pose", args.initial_pose.has_value()}};
  } else {
    j["first_fix"] = nullptr;
  }
  if (ground_truth) {
    dlo::metrics::Trajectory estimate;
    for (const dlo::LocalizationStep& s : steps) {
      if (s.localised) estimate.push_back(s.time, s.pose);
    }
    const auto pairs = dlo::metrics::matchTimestamps(estimate, *ground_truth, 0.005);
    std::vector<double> errors;
    for (const auto& [e, g] : pairs) {
      errors.push_back(
          (estimate.poses[e].translation() - ground_truth->poses[g].translation()).norm());
    }
    const dlo::metrics::ErrorStatistics stats = dlo::metrics::errorStatistics(errors);
    j["accuracy"] = {
        {"matched_poses", pairs.size()}, {"ate_rmse_m", stats.rmse}, {"ate_max_m", stats.max}};
  }
  j["interrupted"] = interrupted;
  j["input_error"] = input_error;
  j["config"] = dlo::localizerParamsToIni(localizer.params()) + "\n" + dlo::slamParamsToIni(params);
  return j;
}

int run(const Arguments& args) {
  // Every layer is checked before the input is read (with auto, on the dense profile's keys).
  std::vector<std::string> slam_sets, localizer_sets;
  dlo::splitLocalizerOverrides(args.sets, slam_sets, localizer_sets);
  const dlo::SlamConfigLayers layers{args.config, slam_sets};
  const bool auto_profile = args.sensor_profile == "auto";
  dlo::SlamParams params =
      dlo::resolveSlamParams(auto_profile ? "dense" : args.sensor_profile, layers);
  dlo::LocalizerParams localizer_params = dlo::resolveLocalizerParams(
      auto_profile ? "dense" : args.sensor_profile, args.config, localizer_sets);
  if (args.dump_config) {
    std::cout << dlo::localizerParamsToIni(localizer_params) << "\n"
              << dlo::slamParamsToIni(params);
    return 0;
  }
  std::optional<dlo::metrics::Trajectory> ground_truth;
  if (!args.gt.empty()) {
    try {
      ground_truth = dlo::metrics::readTrajectory(args.gt);
    } catch (const std::exception& e) {
      throw dlo::InputError("cannot read ground truth '" + args.gt + "': " + e.what());
    }
  }
  dlo::PriorMap map = dlo::loadPriorMap(args.map);
  std::unique_ptr<dlo::ScanSource> source = dlo::openScanSource(
      args.input, args.scans.model,
      dlo::ScanSourceOptions{args.scans.min_range, args.scans.max_range, args.scans.sensor_label});
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (!std::filesystem::is_directory(args.out)) {
    throw dlo::InputError("cannot create output folder '" + args.out + "'.");
  }
  const std::filesystem::path out(args.out);

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  dlo::TimedScan scan;
  bool have = source->next(scan);
  dlo::SensorProfileChoice profile{args.sensor_profile, "--sensor-profile", {}};
  if (auto_profile && have) {
    profile =
        dlo::chooseSensorProfile(dlo::sensorEvidence(scan.points, scan.beams, scan.sensor_pose));
    params = dlo::resolveSlamParams(profile.name, layers);
    localizer_params = dlo::resolveLocalizerParams(profile.name, args.config, localizer_sets);
  }
  dlo::Localizer localizer(std::move(map), localizer_params, params);
  if (args.initial_pose) localizer.setInitialPose(*args.initial_pose);

  dlo::metrics::TumWriter trajectory(
      (out / "trajectory.tum").string(),
      "# dlo-localize: timestamp x y z qx qy qz qw in the map's frame\n");
  std::string csv =
      "time,localised,searched,found,confidence,rms_m,inliers,x,y,z,yaw_deg,ms,odometry\n";
  std::vector<dlo::LocalizationStep> steps;
  dlo::ProgressBar bar(0, "scans", !args.quiet);
  while (have && !g_stop &&
         (args.scans.max_frames < 0 || static_cast<long>(steps.size()) < args.scans.max_frames)) {
    const dlo::LocalizationStep s = localizer.process(
        scan.timestampSeconds(), std::move(scan.points), std::move(scan.point_times));
    if (s.localised) trajectory.write(s.time, s.pose);
    const Eigen::Vector3d p = s.pose.translation();
    char line[256];
    std::snprintf(line, sizeof line, "%.6f,%d,%d,%d,%.3f,%.4f,%.3f,%.4f,%.4f,%.4f,%.3f,%.3f,%d\n",
                  s.time, s.localised, s.searched, s.found, s.confidence, s.rms, s.inliers, p.x(),
                  p.y(), p.z(), dlo::yawPitchRoll(s.pose.linear()).x() * 180.0 / M_PI, s.ms,
                  s.odometry);
    csv += line;
    steps.push_back(s);
    bar.update(steps.size());
    have = source->next(scan);
  }
  bar.finish(steps.size());
  const bool interrupted = g_stop;
  const std::string input_error = source->stats().error;
  if (!input_error.empty()) std::cerr << "dlo-localize: warning: " << input_error << "\n";
  if (steps.empty()) {
    throw dlo::InputError("input '" + args.input + "' holds no usable scan.\n" +
                          dlo::describeScanSourceStats(source->stats()));
  }
  trajectory.commit();
  dlo::writeBytesAtomically((out / "localization.csv").string(),
                            std::vector<unsigned char>(csv.begin(), csv.end()));
  dlo::writeLocalizationImage(localizer.map(), steps, (out / "localization.png").string());
  const Json j =
      report(args, localizer, steps, profile.name, params, ground_truth, interrupted, input_error);
  const std::string text = j.dump(2) + "\n";
  dlo::writeBytesAtomically((out / "report.json").string(),
                            std::vector<unsigned char>(text.begin(), text.end()));
  std::cout << "dlo-localize: " << steps.size() << " scans, " << j["localised_scans"].get<size_t>()
            << " localised (" << 100.0 * j["localised_fraction"].get<double>() << " %), "
            << j["relocalisations"].get<size_t>() << " re-localisations; "
            << j["ms_per_scan"]["median"].get<double>() << " ms/scan median";
  if (j.contains("accuracy")) {
    std::cout << "; position error " << j["accuracy"]["ate_rmse_m"].get<double>() << " m RMS";
  }
  std::cout << "; outputs in '" << args.out << "'" << (interrupted ? " (interrupted)" : "")
            << ".\n";
  return interrupted ? 3 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-localize", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
