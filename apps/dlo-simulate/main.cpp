// dlo-simulate: writes a simulated rotating-LiDAR sequence (MRPT rawlog + TUM ground truth).
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "dlo/sim/lidar_model.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"
#include "velodyne_observation.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: dlo-simulate --out DIR [--frames N] [--sensor HDL64|HDL32|VLP16] [--seed S]
                    [--corner-transition M] [--patrol [--speed V] [--turn-rate W]]
                    [--hills G] [--open-road] [--stops]
                    [--no-point-times] [--threads T] [--quiet] [--help]

Simulates a LiDAR on a car driving laps around a 60 x 40 m block of a procedural town on
rolling hills (roads with crown and kerbs, buildings, trees, poles, parked and moving cars),
turning each corner on a 10 m radius entered and left along 8 m clothoids (the yaw rate ramps
up and down over about a second, as when steering), and writes:
  DIR/sequence.rawlog   one mrpt::obs::CObservationVelodyneScan per sweep (label "LIDAR"):
                        point_cloud holds the points in the sensor frame with per-point
                        timestamps (motion distortion, range noise and dropouts included),
                        scan_packets the same returns as Velodyne packets; sensorPose is the
                        mounting pose on the vehicle (see datasets/README.md)
  DIR/groundtruth.tum   "timestamp x y z qx qy qz qw" of the vehicle frame in the world at
                        each sweep's reference time (its first firing)

Options:
  --out DIR      output folder (created if missing)
  --frames N     number of sweeps, 10 per second (default 300)
  --sensor S     VLP16, HDL32 or HDL64 (default HDL64)
  --seed S       world and noise seed; the same seed gives byte-identical files (default 1)
  --corner-transition M
                 metres of clothoid over which each corner's curvature ramps up and down
                 (default 8); 0 makes circular corners, whose yaw rate steps from zero to
                 about 34 deg/s and back within a firing, as a brisk driver or a robot does
  --patrol       a robot's patrol instead of the car's laps: around the same block at
                 --speed, stopping at each crossing to turn 90 deg on the spot at
                 --turn-rate (the yaw rate steps), after turning round twice (180 deg) at
                 the start; about 170 s per lap at 1.5 m/s
  --speed V      patrol speed, m/s in [0.2, 5] (default 1.5)
  --turn-rate W  patrol turn rate on the spot, deg/s in [10, 180] (default 90)
  --hills G      steep hills instead of the gentle ones: the ground's grade (with the road's
                 crown) stays within G in [0.05, 0.3] (0.2 = 20 %) and the drive reaches
                 about 0.75 G between crests and dips every ~55 m; the car pitches and rolls
                 with the road, everything stands on the ground
  --open-road    an open road instead of the town: the car drives at 15 m/s along a 585 m
                 straight (then round a 1200 x 150 m rectangle) through grass, kerbs on both
                 sides, a pole every ~60 m and a clump of trees every ~200 m, so that the
                 scans constrain little along the road
  --stops        hard stops: 6 s into the drive and every 12 s after, the car brakes at
                 7 m/s^2 to a standstill, waits 2 s and accelerates again at 2.5 m/s^2
  --no-point-times
                 write each sweep as an mrpt::obs::CObservationPointCloud of the same points
                 (sensor frame, firing order, motion distortion included) without per-point
                 times, as KITTI files and most point-cloud inputs come
  --threads T    worker threads (default 2); the output does not depend on it
  --quiet        no progress on stderr
  --help         prints this text

Exit status: 0 on success, 1 for a bad argument or an output that cannot be written; errors
are one line on stderr starting with "dlo-simulate: ".
)";

/// A mistake the user can fix: one sentence, exit status 1.
struct UserError {
  std::string message;
};

struct Arguments {
  std::string out;
  int frames = 300;
  dlo::sim::SensorType sensor = dlo::sim::SensorType::HDL64;
  uint32_t seed = 1;
  int threads = 2;
  double corner_transition = 8.0;
  bool patrol = false;
  double speed = 1.5;
  double turn_rate = 90.0;
  double hills = 0.0;
  bool open_road = false;
  bool stops = false;
  bool no_point_times = false;
  bool quiet = false;
  bool help = false;
};

/// `text` read whole by `read` (std::stol or std::stod) and within [lo, hi], or a UserError
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
  throw UserError{name + " must be " + expected + ", got '" + text + "'."};
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

Arguments parseArguments(int argc, char** argv) {
  Arguments a;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      a.help = true;
      return a;
    }
    if (arg == "--quiet") {
      a.quiet = true;
      continue;
    }
    if (arg == "--patrol") {
      a.patrol = true;
      continue;
    }
    if (arg == "--no-point-times") {
      a.no_point_times = true;
      continue;
    }
    if (arg == "--open-road") {
      a.open_road = true;
      continue;
    }
    if (arg == "--stops") {
      a.stops = true;
      continue;
    }
    std::string value;
    const auto eq = arg.find('=');
    if (eq != std::string::npos && arg.rfind("--", 0) == 0) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    } else if (arg == "--out" || arg == "--frames" || arg == "--sensor" || arg == "--seed" ||
               arg == "--threads" || arg == "--corner-transition" || arg == "--speed" ||
               arg == "--turn-rate" || arg == "--hills") {
      if (i + 1 >= argc) throw UserError{arg + " needs a value."};
      value = argv[++i];
    }
    if (arg == "--out") {
      a.out = value;
    } else if (arg == "--frames") {
      a.frames = static_cast<int>(parseInteger("--frames", value, 1, 10000000, "an integer >= 1"));
    } else if (arg == "--sensor") {
      const auto s = dlo::sim::parseSensorType(value);
      if (!s) throw UserError{"--sensor must be VLP16, HDL32 or HDL64, got '" + value + "'."};
      a.sensor = *s;
    } else if (arg == "--seed") {
      a.seed = static_cast<uint32_t>(
          parseInteger("--seed", value, 0, 4294967295L, "an integer in [0, 4294967295]"));
    } else if (arg == "--corner-transition") {
      a.corner_transition =
          parseNumber("--corner-transition", value, 0.0, 15.0, "a number of metres in [0, 15]");
    } else if (arg == "--speed") {
      a.speed = parseNumber("--speed", value, 0.2, 5.0, "a speed in [0.2, 5] m/s");
    } else if (arg == "--turn-rate") {
      a.turn_rate = parseNumber("--turn-rate", value, 10.0, 180.0, "a rate in [10, 180] deg/s");
    } else if (arg == "--hills") {
      a.hills = parseNumber("--hills", value, 0.05, 0.3, "a grade in [0.05, 0.3]");
    } else if (arg == "--threads") {
      a.threads =
          static_cast<int>(parseInteger("--threads", value, 1, 64, "an integer in [1, 64]"));
    } else {
      throw UserError{"unknown argument '" + arg + "' (see --help)."};
    }
  }
  if (a.out.empty()) throw UserError{"--out DIR is required (see --help)."};
  return a;
}

/// "seconds.nanoseconds" without going through a double.
std::string tumTimestamp(int64_t epochSeconds, int64_t ns) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%" PRId64 ".%09" PRId64, epochSeconds + ns / 1000000000,
                ns % 1000000000);
  return buf;
}

std::string tumLine(const std::string& stamp, const Eigen::Isometry3d& pose) {
  Eigen::Quaterniond q(pose.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;  // One sign, so that files compare equal.
  const Eigen::Vector3d t = pose.translation();
  char buf[256];
  std::snprintf(buf, sizeof(buf), "%s %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", stamp.c_str(), t.x(),
                t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  return buf;
}

int run(const Arguments& a) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(a.out, ec);
  if (ec) throw UserError{"--out: cannot create directory '" + a.out + "': " + ec.message() + "."};
  const fs::path rawlogPath = fs::path(a.out) / "sequence.rawlog";
  const fs::path tumPath = fs::path(a.out) / "groundtruth.tum";
  const fs::path rawlogTmp = rawlogPath.string() + ".part", tumTmp = tumPath.string() + ".part";

  mrpt::io::CFileOutputStream rawlog;
  if (!rawlog.open(rawlogTmp.string())) {
    throw UserError{"--out: cannot write to directory '" + a.out + "'."};
  }
  std::FILE* tum = std::fopen(tumTmp.string().c_str(), "w");
  if (!tum) throw UserError{"--out: cannot write to directory '" + a.out + "'."};

  // A whole hour (2024-01-01T00:00:00Z), so that the packets' "microseconds since the top of
  // the hour" equal the time since the start, modulo one hour.
  constexpr int64_t kEpochSeconds = 1704067200;
  const mrpt::Clock::time_point epoch = mrpt::Clock::fromDouble(static_cast<double>(kEpochSeconds));

  dlo::sim::WorldParams town;
  dlo::sim::OpenRoadParams road;
  town.maxGrade = road.maxGrade = a.hills;
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
  params.seed = a.seed;
  params.threads = a.threads;
  const dlo::sim::SweepSimulator simulator(world, trajectory, params);

  std::fprintf(tum,
               "# dlo-simulate ground truth: timestamp x y z qx qy qz qw of the vehicle "
               "frame in the world, sensor %s, seed %u, sensor mounted at x=%.2f y=%.2f "
               "z=%.2f on the vehicle\n",
               params.model.name.c_str(), a.seed, trajectory.geometry().sensorPosition.x(),
               trajectory.geometry().sensorPosition.y(), trajectory.geometry().sensorPosition.z());

  auto archive = mrpt::serialization::archiveFrom(rawlog);
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < a.frames; ++k) {
    const dlo::sim::Sweep sweep = simulator.simulate(k);
    const auto obs =
        dlo::toVelodyneScan(sweep, simulator, trajectory.sensorMount(), epoch, "LIDAR");
    if (a.no_point_times) {
      archive << *dlo::withoutPointTimes(*obs);
    } else {
      archive << *obs;
    }
    const Eigen::Isometry3d pose =
        trajectory.vehiclePose(static_cast<double>(sweep.referenceTimeNs) * 1e-9);
    std::fputs(tumLine(tumTimestamp(kEpochSeconds, sweep.referenceTimeNs), pose).c_str(), tum);
    if (!a.quiet && ((k + 1) % 10 == 0 || k + 1 == a.frames)) {
      const double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "dlo-simulate: %d / %d frames, %.1f frames/s\n", k + 1, a.frames,
                   (k + 1) / std::max(s, 1e-9));
    }
  }
  rawlog.close();
  const bool tumOk = std::fclose(tum) == 0;
  if (!tumOk) throw UserError{"--out: failed writing '" + tumTmp.string() + "'."};
  fs::rename(rawlogTmp, rawlogPath, ec);
  if (!ec) fs::rename(tumTmp, tumPath, ec);
  if (ec)
    throw UserError{"--out: cannot rename the output files in '" + a.out + "': " + ec.message() +
                    "."};
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Arguments a = parseArguments(argc, argv);
    if (a.help) {
      std::cout << kUsage;
      return 0;
    }
    return run(a);
  } catch (const UserError& e) {
    std::cerr << "dlo-simulate: " << e.message << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "dlo-simulate: " << e.what() << "\n";
    return 1;
  }
}
