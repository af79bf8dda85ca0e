// dlo-simulate: writes a simulated rotating-LiDAR sequence (MRPT rawlog + TUM ground truth).
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/files/atomic_file.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/rawlog_writer.h"
#include "dlo/sim/lidar_model.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"
#include "sweep_observations.h"
#include "velodyne_observation.h"

namespace {

constexpr const char* kDescription =
    "Simulates a LiDAR on a car driving laps around a 60 x 40 m block of a procedural town on "
    "rolling hills (roads with crown and kerbs, buildings, trees, poles, parked and moving cars), "
    "turning each corner on a 10 m radius entered and left along 8 m clothoids (the yaw rate "
    "ramps up and down over about a second, as when steering), and writes DIR/sequence.rawlog "
    "and DIR/groundtruth.tum.";

constexpr const char* kFooter = R"(Outputs:
  DIR/sequence.rawlog   one mrpt::obs::CObservationVelodyneScan per sweep (label "LIDAR"):
                        point_cloud holds the points in the sensor frame with per-point
                        timestamps (motion distortion, range noise and dropouts included),
                        scan_packets the same returns as Velodyne packets; sensorPose is the
                        mounting pose on the vehicle (see datasets/README.md); OS64 and
                        OS128 sweeps, which Velodyne packets cannot hold, are written as
                        mrpt::obs::CObservationRotatingScan range images (lidarModel
                        OS1-64 / OS1-128, one time per column)
  DIR/groundtruth.tum   "timestamp x y z qx qy qz qw" of the vehicle frame in the world at
                        each sweep's reference time (its first firing)

Exit status: 0 on success, 1 for an output that cannot be written, 2 for a bad argument;
errors are one line on stderr starting with "dlo-simulate: ".)";

using dlo::OutputError;
using dlo::UsageError;

struct Arguments {
  std::string out;
  int frames = 300;
  dlo::sim::SensorType sensor = dlo::sim::SensorType::HDL64;
  uint32_t seed = 1;
  uint32_t traffic_seed = 0;  // 0: the cars and the noise from `seed`
  int threads = 2;
  double corner_transition = 8.0;
  bool patrol = false;
  double speed = 1.5;
  double turn_rate = 90.0;
  double hills = 0.0;
  bool open_road = false;
  bool large_loop = false;
  bool stops = false;
  bool no_point_times = false;
  double sweep_start = 0.0;
  int spin = -1;  // -1 clockwise, +1 counter-clockwise
  bool quiet = false;
};

/// `text` read whole by `read` (std::stol or std::stod) and within [lo, hi], or a UsageError
/// naming the option and what it expects.
template <typename T, typename Read>
T parseValue(const std::string& name, const std::string& text, T lo, T hi,
             const std::string& expected, Read read) {
  try {
    size_t used = 0;
    const T v = read(text, &used);
    if (used == text.size() && v >= lo && v <= hi) return v;
  } catch (const std::exception&) {
  }
  throw UsageError{name + " must be " + expected + ", got '" + text + "'."};
}

long parseInteger(const std::string& name, const std::string& text, long lo, long hi,
                  const std::string& expected) {
  return parseValue<long>(name, text, lo, hi, expected,
                          [](const std::string& s, size_t* used) { return std::stol(s, used); });
}

double parseNumber(const std::string& name, const std::string& text, double lo, double hi,
                   const std::string& expected) {
  return parseValue<double>(name, text, lo, hi, expected,
                            [](const std::string& s, size_t* used) { return std::stod(s, used); });
}

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  // The numbers are read here, not by the parser, for their ranges and messages.
  std::string frames, sensor, seed, traffic_seed, corner_transition, speed, turn_rate, hills,
      sweep_start, spin, threads;
  dlo::ProgramOptions cl("dlo-simulate", kDescription);
  cl.text("--out", a.out, "output folder (created if missing)").valueName("DIR").required();
  cl.text("--frames", frames, "number of sweeps, 10 per second").valueName("N").defaultText("300");
  cl.text("--sensor", sensor,
          "VLP16, HDL32, HDL64 (Velodyne), OS64 or OS128 (Ouster OS1-like: 64 or 128 beams "
          "evenly over +22.5..-22.5 deg, 1024 columns, 0.5-120 m)")
      .valueName("S")
      .defaultText("HDL64");
  cl.text("--seed", seed, "world and noise seed; the same seed gives byte-identical files")
      .valueName("S")
      .defaultText("1");
  cl.text("--traffic-seed", traffic_seed,
          "another day in the same town: the parked and moving cars and the sensor noise from T, "
          "the streets, buildings, trees and poles from --seed (the town only; for localising a "
          "drive on a map of another)")
      .valueName("T");
  cl.text("--corner-transition", corner_transition,
          "metres of clothoid over which each corner's curvature ramps up and down; 0 makes "
          "circular corners, whose yaw rate steps from zero to about 34 deg/s and back within a "
          "firing, as a brisk driver or a robot does")
      .valueName("M")
      .defaultText("8");
  cl.flag("--patrol", a.patrol,
          "a robot's patrol instead of the car's laps: around the same block at --speed, "
          "stopping at each crossing to turn 90 deg on the spot at --turn-rate (the yaw rate "
          "steps), after turning round twice (180 deg) at the start; about 170 s per lap at "
          "1.5 m/s");
  cl.text("--speed", speed, "patrol speed, m/s in [0.2, 5]").valueName("V").defaultText("1.5");
  cl.text("--turn-rate", turn_rate, "patrol turn rate on the spot, deg/s in [10, 180]")
      .valueName("W")
      .defaultText("90");
  cl.text("--hills", hills,
          "steep hills instead of the gentle ones: the ground's grade (with the road's crown) "
          "stays within G in [0.05, 0.3] (0.2 = 20 %) and the drive reaches about 0.75 G between "
          "crests and dips every ~55 m; the car pitches and rolls with the road, everything "
          "stands on the ground")
      .valueName("G");
  cl.flag("--open-road", a.open_road,
          "an open road instead of the town: the car drives at 15 m/s along a 585 m straight "
          "(then round a 1200 x 150 m rectangle) through grass, kerbs on both sides, a pole every "
          "~60 m and a clump of trees every ~200 m, so that the scans constrain little along the "
          "road");
  cl.flag("--large-loop", a.large_loop,
          "laps of the 180 x 120 m rectangle of town roads around the 3 x 3 blocks centred on the "
          "default block instead of that block alone: 180 m straights through four crossings "
          "with cross traffic, about 600 m per lap, new buildings along most of it");
  cl.flag("--stops", a.stops,
          "hard stops: 6 s into the drive and every 12 s after, the car brakes at 7 m/s^2 to a "
          "standstill, waits 2 s and accelerates again at 2.5 m/s^2");
  cl.flag("--no-point-times", a.no_point_times,
          "write each sweep as an mrpt::obs::CObservationPointCloud of the same points (sensor "
          "frame, firing order, motion distortion included) without per-point times, as KITTI "
          "files and most point-cloud inputs come");
  cl.text("--sweep-start", sweep_start,
          "azimuth where each sweep starts, degrees counter-clockwise from the sensor's forward "
          "axis, in [-360, 360] (0: forward)")
      .valueName("DEG")
      .defaultText("0");
  cl.text("--spin", spin,
          "rotation of the head seen from above: cw (as Velodyne and Ouster sensors) or ccw")
      .valueName("D")
      .defaultText("cw");
  cl.text("--threads", threads, "worker threads; the output does not depend on it")
      .valueName("T")
      .defaultText("2");
  cl.flag("--quiet", a.quiet, "no progress on stderr");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (cl.given("--frames")) {
    a.frames = static_cast<int>(parseInteger("--frames", frames, 1, 10000000, "an integer >= 1"));
  }
  if (cl.given("--sensor")) {
    const auto s = dlo::sim::parseSensorType(sensor);
    if (!s) {
      throw UsageError{"--sensor must be VLP16, HDL32, HDL64, OS64 or OS128, got '" + sensor +
                       "'."};
    }
    a.sensor = *s;
  }
  if (cl.given("--seed")) {
    a.seed = static_cast<uint32_t>(
        parseInteger("--seed", seed, 0, 4294967295L, "an integer in [0, 4294967295]"));
  }
  if (cl.given("--traffic-seed")) {
    a.traffic_seed = static_cast<uint32_t>(parseInteger(
        "--traffic-seed", traffic_seed, 1, 4294967295L, "an integer in [1, 4294967295]"));
    if (a.open_road) throw UsageError{"--traffic-seed applies to the town, not --open-road."};
  }
  if (a.large_loop && a.open_road) {
    throw UsageError{"--large-loop is a loop of the town; it cannot be combined with --open-road."};
  }
  if (cl.given("--corner-transition")) {
    a.corner_transition = parseNumber("--corner-transition", corner_transition, 0.0, 15.0,
                                      "a number of metres in [0, 15]");
  }
  if (cl.given("--speed")) {
    a.speed = parseNumber("--speed", speed, 0.2, 5.0, "a speed in [0.2, 5] m/s");
  }
  if (cl.given("--turn-rate")) {
    a.turn_rate = parseNumber("--turn-rate", turn_rate, 10.0, 180.0, "a rate in [10, 180] deg/s");
  }
  if (cl.given("--hills")) {
    a.hills = parseNumber("--hills", hills, 0.05, 0.3, "a grade in [0.05, 0.3]");
  }
  if (cl.given("--sweep-start")) {
    a.sweep_start =
        parseNumber("--sweep-start", sweep_start, -360.0, 360.0, "an angle in [-360, 360] degrees");
  }
  if (cl.given("--spin")) {
    if (spin != "cw" && spin != "ccw") {
      throw UsageError{"--spin must be cw or ccw, got '" + spin + "'."};
    }
    a.spin = spin == "cw" ? -1 : 1;
  }
  if (cl.given("--threads")) {
    a.threads =
        static_cast<int>(parseInteger("--threads", threads, 1, 64, "an integer in [1, 64]"));
  }
  return a;
}

int run(const Arguments& a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) {
    throw OutputError{"--out: cannot create directory '" + a.out + "': " + ec.message() + "."};
  }
  // Both files are written under temporary names and renamed at the end (dlo::AtomicOutput).
  std::optional<dlo::RawlogWriter> rawlog;
  try {
    rawlog.emplace((fs::path(a.out) / "sequence.rawlog").string());
  } catch (const dlo::Error&) {
    throw OutputError{"--out: cannot write to directory '" + a.out + "'."};
  }

  // A whole hour (2024-01-01T00:00:00Z), so that the packets' "microseconds since the top of
  // the hour" equal the time since the start, modulo one hour.
  constexpr int64_t kEpochSeconds = 1704067200;
  const mrpt::Clock::time_point epoch = mrpt::Clock::fromDouble(static_cast<double>(kEpochSeconds));

  dlo::sim::WorldParams town;
  dlo::sim::OpenRoadParams road;
  town.maxGrade = road.maxGrade = a.hills;
  town.trafficSeed = a.traffic_seed;
  if (a.large_loop) {
    // The roads one crossing out from the default block on every side.
    town.loopMin = {town.roadsX[1], town.roadsY[1]};
    town.loopMax = {town.roadsX[4], town.roadsY[4]};
  }
  const auto world = a.open_road ? dlo::sim::ProceduralWorld::generateOpenRoad(a.seed, road)
                                 : dlo::sim::ProceduralWorld::generate(a.seed, town);
  const Eigen::Vector2d lo = a.open_road ? road.loopMin : town.loopMin;
  const Eigen::Vector2d hi = a.open_road ? road.loopMax : town.loopMax;
  dlo::sim::SpeedLimits limits;
  if (a.open_road) limits.cruise = road.cruise;
  auto route = a.patrol ? dlo::sim::Route::patrol(lo, hi, a.speed, a.turn_rate)
                        : dlo::sim::Route::roundedRectangle(lo, hi, /*radius=*/10.0,
                                                            a.corner_transition, limits);
  if (a.stops) route.setStops(dlo::sim::StopParams(), a.frames * 0.1 + 1.0);
  const dlo::sim::VehicleTrajectory trajectory(route, world.terrain());
  dlo::sim::SweepSimulatorParams params;
  params.model = dlo::sim::makeLidarModel(a.sensor);
  params.model.sweepStartDeg = a.sweep_start;
  params.model.spinDirection = a.spin;
  params.seed = a.traffic_seed != 0 ? a.traffic_seed : a.seed;
  params.threads = a.threads;
  const dlo::sim::SweepSimulator simulator(world, trajectory, params);

  char header[512];
  std::snprintf(header, sizeof(header),
                "# dlo-simulate ground truth: timestamp x y z qx qy qz qw of the vehicle "
                "frame in the world, sensor %s, seed %u, sensor mounted at x=%.2f y=%.2f "
                "z=%.2f on the vehicle\n",
                params.model.name.c_str(), a.seed, trajectory.geometry().sensorPosition.x(),
                trajectory.geometry().sensorPosition.y(), trajectory.geometry().sensorPosition.z());
  dlo::metrics::TumWriter groundTruth((fs::path(a.out) / "groundtruth.tum").string(), header);

  const Eigen::Isometry3d mount = trajectory.sensorMount();
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < a.frames; ++k) {
    const dlo::sim::Sweep sweep = simulator.simulate(k);
    if (a.no_point_times) {
      rawlog->write(*dlo::withoutPointTimes(sweep, simulator, mount, epoch, "LIDAR"));
    } else if (params.model.velodyne()) {
      rawlog->write(*dlo::toVelodyneScan(sweep, simulator, mount, epoch, "LIDAR"));
    } else {
      rawlog->write(*dlo::toRotatingScan(sweep, simulator, mount, epoch, "LIDAR"));
    }
    const Eigen::Isometry3d pose =
        trajectory.vehiclePose(static_cast<double>(sweep.referenceTimeNs) * 1e-9);
    groundTruth.write(kEpochSeconds, sweep.referenceTimeNs, pose);
    if (!a.quiet && ((k + 1) % 10 == 0 || k + 1 == a.frames)) {
      const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "dlo-simulate: %d / %d frames, %.1f frames/s\n", k + 1, a.frames,
                   (k + 1) / std::max(s, 1e-9));
    }
  }
  rawlog->commit();
  groundTruth.commit();
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-simulate", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
