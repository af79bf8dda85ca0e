// dlo-slam: LiDAR odometry, keyframe pose graph and loop closure over a rawlog or a Velodyne
// capture, with GUI-free map export. The pipeline lives in libs/slam; this file parses the
// command line, streams the input, and reports.
#include <atomic>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/app/scan_input_options.h"
#include "dlo/core/deskew.h"
#include "dlo/export/annotated_rawlog.h"
#include "dlo/export/export_all.h"
#include "dlo/files/atomic_file.h"
#include "dlo/files/error.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/kitti_scan_source.h"
#include "dlo/mrpt/open_scan_source.h"
#include "dlo/slam/lidar_odometry.h"
#include "dlo/slam/sensor_profile.h"
#include "dlo/slam/slam_config.h"
#include "dlo/slam/slam_pipeline.h"
#include "dlo/slam/slam_report.h"

namespace {

constexpr const char* kDescription =
    "Runs DLO odometry with a keyframe pose graph and loop closure over the LiDAR scans of IN and "
    "writes the trajectory, the pose graph, maps and a report into DIR (created if needed), each "
    "file atomically.";

constexpr const char* kFooter = R"(Outputs in DIR:
  trajectory.tum, trajectory.kitti   one pose per scan, vehicle frame, relative to the first scan
  keyframes.graph                    optimised pose graph (MRPT graph-slam reads it)
  map.simplemap                      keyframes with their point clouds (CSimpleMap)
  heightmap.bin, heightmap.png       CHeightGridMap2D of the whole area; colour image with the
                                     trajectory and loop closures
  heightmap_centroids.bin            where in each height map cell its points lie (dlo-localize)
  map.gridmap, map.png, map.yaml     2D occupancy grid (COccupancyGridMap2D for MRPT's
                                     localisation and navigation; image and ROS map_server YAML):
                                     obstacles rise more than --obstacle-height above the ground
  map.ply                            voxel-downsampled point-cloud map
  map.3Dscene, map_render.png        3D scene, and its off-screen rendering
  --rawlog-out FILE                  the input's scans again, with the estimated motion between
                                     them: (action, sensory frame) pairs for MRPT's tools, each
                                     frame with the scan's observation and an emulated 2D laser
                                     scan of the obstacles map.gridmap marks
  report.json                        ms per frame (median, p95), stages, keyframes, loops,
                                     degenerate frames, peak memory, configuration, and with
                                     --gt: ATE and KITTI drift before and after loop closure

Input:
  IN.rawlog / IN.rawlog.gz   MRPT rawlog, either layout: Velodyne scans, point clouds, 3D range
                             scans;
  IN.pcap                    Velodyne capture; needs --model;
  KITTI folder               a KITTI odometry sequence (velodyne/*.bin[.gz], times.txt, and
                             optionally poses.txt + calib.txt, then used as --gt unless given);
                             points stay in the LiDAR frame.

SIGINT or SIGTERM stops the run after the current scan; the outputs for what was processed are
written, then dlo-slam exits with status 3.
Exit status: 0 on success, 1 for a bad input file or parameter, 2 for a command-line error,
3 when interrupted; errors are one line on stderr starting with "dlo-slam: ".)";

std::atomic<bool> g_stop{false};
void onSignal(int) {
  g_stop = true;
}

using dlo::UsageError;

struct Arguments {
  std::string input, out, config, gt, sensor_profile = "auto", rawlog_out;
  std::vector<std::string> sets;
  dlo::ScanInputOptions scans;
  double obstacle_height = dlo::OccupancyGridOptions().obstacle_height;
  bool quiet = false, dump_config = false;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-slam", kDescription);
  cl.text("--input", a.input,
          "a rawlog, a Velodyne .pcap or a KITTI folder (see Input); required unless "
          "--dump-config")
      .valueName("IN");
  cl.text("--out", a.out, "output folder; required unless --dump-config").valueName("DIR");
  cl.text("--config", a.config,
          "MRPT INI with [grid] [selection] [solver] [odometry] [loop]; see config/dlo-slam.ini "
          "(every key commented) or --dump-config")
      .valueName("FILE");
  cl.repeatable("--set", a.sets, "overrides one parameter after --config; may be repeated")
      .valueName("section.key=value");
  cl.text("--sensor-profile", a.sensor_profile,
          "the settings for the kind of sensor, applied before --config and --set: dense (48 "
          "rings or more), sparse (fewer), or a profile file; auto picks dense or sparse from the "
          "input's sensor model, else from the rings of its first scan, else from its point "
          "count (report.json says which and why). The profiles: config/sensors/*.ini")
      .valueName("auto|dense|sparse|FILE");
  cl.text("--gt", a.gt, "ground truth (TUM or KITTI poses) for report.json's accuracy")
      .valueName("FILE");
  dlo::declareScanInputOptions(cl, a.scans, dlo::kScanAll);
  cl.number("--obstacle-height", a.obstacle_height,
            "metres above the local ground from which a point makes its cell an obstacle in "
            "map.gridmap (kerbs stay free)")
      .valueName("M");
  cl.text("--rawlog-out", a.rawlog_out,
          "also write the scans as an annotated rawlog: the estimated motion as actions, each "
          "scan's observation and an emulated 2D laser scan (see Outputs); .gz compresses it")
      .valueName("FILE");
  cl.flag("--quiet", a.quiet, "no progress bar");
  cl.flag("--dump-config", a.dump_config,
          "print the effective configuration as INI and exit (with auto, the dense profile's)");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (a.dump_config) return a;
  if (a.input.empty()) throw UsageError{"--input is required (see --help)."};
  if (a.out.empty()) throw UsageError{"--out is required (see --help)."};
  dlo::checkScanInputOptions(a.scans);
  const dlo::OccupancyGridOptions occupancy;
  if (!(a.obstacle_height > 0.0 && a.obstacle_height < occupancy.max_height)) {
    throw UsageError{"--obstacle-height must be above 0 and below " +
                     std::to_string(occupancy.max_height).substr(0, 3) + " m."};
  }
  return a;
}

std::unique_ptr<dlo::ScanSource> openSource(const Arguments& a) {
  return dlo::openScanSource(
      a.input, a.scans.model,
      dlo::ScanSourceOptions{a.scans.min_range, a.scans.max_range, a.scans.sensor_label});
}

/// The velocity (body twist per second) of frame i of `map`, from its final pose and its
/// neighbour's (the next one's for the first frame); zero where the interval is not 0-1 s.
dlo::Vector6d frameVelocity(const dlo::SlamMap& map, size_t i) {
  if (map.frames.size() < 2) return dlo::Vector6d::Zero();
  const size_t a = i == 0 ? 0 : i - 1, b = i == 0 ? 1 : i;
  const double dt = map.frames[b].time - map.frames[a].time;
  if (!(dt > 0.0 && dt < 1.0)) return dlo::Vector6d::Zero();
  return dlo::logSE3(map.framePose(a).inverse() * map.framePose(b)) / dt;
}

/// Reads the input again and writes its first map.frames.size() scans, each at its final pose
/// and deskewed with the motion there, into args.rawlog_out.
void writeAnnotatedRawlog(const Arguments& args, const dlo::SlamParams& params,
                          const dlo::SlamMap& map) {
  std::unique_ptr<dlo::ScanSource> source = openSource(args);
  dlo::Emulated2DScanOptions options;
  options.obstacles.obstacle_height = args.obstacle_height;
  dlo::AnnotatedRawlogWriter writer(args.rawlog_out, options);
  dlo::ProgressBar bar(map.frames.size(), "scans to " + args.rawlog_out, !args.quiet);
  dlo::TimedScan scan;
  std::vector<float> times;
  dlo::SweepPeriodEstimate period;  // as the odometry estimated it
  for (size_t i = 0; i < map.frames.size(); ++i) {
    if (!source->next(scan) || std::abs(scan.timestampSeconds() - map.frames[i].time) > 1e-6) {
      throw dlo::InputError("input '" + args.input + "' did not give the same scans when read " +
                            "again for --rawlog-out (scan " + std::to_string(i) + "); the " +
                            std::to_string(writer.count()) + " written are kept in '" +
                            writer.partialPath() + "'.");
    }
    dlo::PointTimeSource source;
    period.add(scan.timestampSeconds());
    const std::vector<float>& t =
        dlo::pointTimesFor(scan.points, scan.point_times, params.odometry,
                           dlo::sweepPeriod(params.odometry, period), times, source);
    writer.write(scan, map.framePose(i),
                 t.empty() ? scan.points : dlo::deskew(scan.points, t, frameVelocity(map, i)));
    bar.update(i + 1);
  }
  writer.commit();
  bar.finish(map.frames.size());
}

int run(const Arguments& args) {
  const dlo::SlamConfigLayers layers{args.config, args.sets};
  const bool auto_profile = args.sensor_profile == "auto";
  // Every layer is checked before the input is read (with auto, on the dense profile's keys).
  dlo::SlamParams params =
      dlo::resolveSlamParams(auto_profile ? "dense" : args.sensor_profile, layers);
  if (args.dump_config) {
    std::cout << dlo::slamParamsToIni(params);
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
  // The input is opened first, so that a wrong path leaves no empty output folder behind.
  std::unique_ptr<dlo::ScanSource> source = openSource(args);
  if (const auto* kitti = dynamic_cast<const dlo::KittiScanSource*>(source.get());
      kitti && !ground_truth && !kitti->sequence().lidar_poses.empty()) {
    // A KITTI folder brings its own ground truth: poses.txt, in the LiDAR frame (calib.txt).
    const dlo::KittiSequence& s = kitti->sequence();
    ground_truth.emplace();
    for (size_t i = 0; i < s.lidar_poses.size(); ++i)
      ground_truth->push_back(s.times[i], s.lidar_poses[i]);
    if (!args.quiet) {
      std::cerr << "dlo-slam: ground truth from the folder's poses.txt"
                << (s.poses_from_camera_frame ? " (camera poses moved to the LiDAR with calib.txt)"
                                              : "")
                << ".\n";
    }
  }
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (!std::filesystem::is_directory(args.out)) {
    throw dlo::InputError("cannot create output folder '" + args.out + "'.");
  }

  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  // The scans up to the first with points, which shows the sensor (empty ones before it are
  // processed too, for their poses).
  std::vector<dlo::TimedScan> first;
  bool ended = false;
  while (first.empty() || first.back().points.empty()) {
    dlo::TimedScan s;
    if (!source->next(s)) {
      ended = true;
      break;
    }
    first.push_back(std::move(s));
  }
  dlo::SensorProfileChoice profile{args.sensor_profile, "--sensor-profile", {}};
  if (!first.empty()) {
    const dlo::TimedScan& s = first.back();
    dlo::SensorConfiguration c = dlo::configureForSensor(
        args.sensor_profile, layers, dlo::sensorEvidence(s.points, s.beams, s.sensor_pose));
    params = std::move(c.params);
    profile = std::move(c.profile);
    if (auto_profile && !args.quiet) {
      std::cerr << "dlo-slam: sensor profile " << profile.name << " (" << profile.reason << ").\n";
    }
  }
  dlo::SlamPipeline slam(params);
  dlo::ProgressBar bar(0, "scans", !args.quiet);
  size_t frames = 0;
  const auto more = [&] {
    return !g_stop &&
           (args.scans.max_frames < 0 || static_cast<long>(frames) < args.scans.max_frames);
  };
  const auto process = [&](const dlo::TimedScan& s) {
    slam.process(s.timestampSeconds(), s.points, s.point_times);
    bar.update(++frames);
  };
  for (const dlo::TimedScan& s : first) {
    if (more()) process(s);
  }
  dlo::TimedScan scan;
  while (!ended && more() && source->next(scan)) process(scan);
  bar.finish(frames);
  slam.sampleMemory();
  const bool interrupted = g_stop;
  const std::string input_error = source->stats().error;
  if (!input_error.empty()) std::cerr << "dlo-slam: warning: " << input_error << "\n";
  if (slam.map().frames.empty()) {
    throw dlo::InputError("input '" + args.input + "' holds no usable scan.\n" +
                          dlo::describeScanSourceStats(source->stats()));
  }

  std::optional<dlo::SlamAccuracy> accuracy;
  if (ground_truth) {
    try {
      accuracy = dlo::evaluateAgainst(slam.map(), *ground_truth);
    } catch (const std::exception& e) {
      std::cerr << "dlo-slam: warning: no accuracy figures: ground truth '" << args.gt
                << "': " << e.what() << "\n";
    }
  }
  dlo::ExportOptions export_options;
  export_options.map_voxel = params.odometry.map_voxel;
  export_options.occupancy.obstacle_height = args.obstacle_height;
  const dlo::ExportReport exported = dlo::exportAll(slam.map(), args.out, export_options);
  for (const std::string& w : exported.warnings) std::cerr << "dlo-slam: warning: " << w << "\n";
  if (!args.rawlog_out.empty()) writeAnnotatedRawlog(args, slam.params(), slam.map());
  const std::string report =
      dlo::slamReportJson(slam, args.input, profile, dlo::slamParamsToIni(slam.params()), accuracy,
                          interrupted, input_error);
  const std::string report_path = (std::filesystem::path(args.out) / "report.json").string();
  dlo::writeBytesAtomically(report_path, std::vector<unsigned char>(report.begin(), report.end()));

  std::vector<double> ms = slam.timings().total;
  std::sort(ms.begin(), ms.end());
  std::cout << "dlo-slam: " << slam.counters().frames << " scans, " << slam.map().keyframes.size()
            << " keyframes, " << slam.counters().loops_accepted << " loops closed ("
            << slam.counters().loops_rejected << " rejected), " << slam.counters().degenerate_frames
            << " degenerate; " << ms[ms.size() / 2] << " ms/scan median";
  const dlo::HeightGridParams& g = slam.params().registration.grid;
  std::cout << "; sensor profile " << profile.name << ": " << g.cols << " x " << g.rows
            << " cells of " << g.resolution << " m";
  if (accuracy) {
    std::cout << "; ATE " << accuracy->ate_rmse_before << " m before, " << accuracy->ate_rmse_after
              << " m after loop closure";
  }
  std::cout << "; outputs in '" << args.out << "'" << (interrupted ? " (interrupted)" : "")
            << ".\n";
  return interrupted ? 3 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-slam", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
