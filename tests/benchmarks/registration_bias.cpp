// Measurement, not a test: how far registrations of two sweeps fall short of (or beyond) the
// motion between them, by the distance between the sweeps. Each sweep of a simulated drive
// through the town is undistorted exactly (every point placed with the vehicle's true pose at
// its own firing time), so nothing but the height grids and the registration can err; each pair
// is registered from the true motion, so the result is where the registration's optimum lies.
//
//   dlo_registration_bias [--seed S] [--sensor MODEL] [--cols N] [--resolution M]
//                         [--centroid-levels L] [--frames N]      (--help: each option)
//
// prints per 0.5 m of distance the pairs, and the median, mean and RMS of the error along the
// motion (negative: the registration measured less motion than there was), in millimetres.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/files/error.h"
#include "dlo/sim/lidar_model.h"
#include "dlo/sim/procedural_world.h"
#include "dlo/sim/route.h"
#include "dlo/sim/sweep_simulator.h"
#include "dlo/sim/vehicle_trajectory.h"

namespace {

struct Options {
  unsigned seed = 1;
  dlo::sim::SensorType sensor = dlo::sim::SensorType::HDL64;
  int frames = 100;
  /// The registration's grid: --cols, --resolution and --centroid-levels on the paper's
  /// defaults, the two finest levels at their centroids as dlo-slam's dense profile has them.
  dlo::DloParams params;
  Options() { params.selection.centroid_levels = 2; }
};

/// The command line; \throw dlo::UsageError for a mistake. \return false when --help was
/// printed.
bool parse(int argc, char** argv, Options& o) {
  dlo::ProgramOptions cl(
      "dlo_registration_bias",
      "Measures how far registrations of two exactly undistorted simulated sweeps fall short of "
      "(or beyond) the motion between them, by the distance between the sweeps: a markdown table "
      "of the median, mean and RMS error along the motion per 0.5 m of distance (millimetres; "
      "negative: less motion measured than there was).");
  long seed = o.seed;
  long cols = o.params.grid.cols;
  long levels = o.params.selection.centroid_levels;
  long frames = o.frames;
  std::string sensor = "HDL64";
  cl.wholeNumber("--seed", seed, "the town's and the sensor's seed").valueName("S");
  cl.text("--sensor", sensor, "VLP16, HDL32, HDL64, OS64 or OS128").valueName("MODEL");
  cl.wholeNumber("--cols", cols, "cells per side of the grid").valueName("N");
  cl.number("--resolution", o.params.grid.resolution, "metres per cell at the finest level")
      .valueName("M");
  cl.wholeNumber("--centroid-levels", levels,
                 "the finest levels compared at their cells' centroids (0: at the centres)")
      .valueName("L");
  cl.wholeNumber("--frames", frames, "sweeps simulated, 30 to 100000").valueName("N");
  if (!cl.parse(argc, argv)) return false;
  const std::optional<dlo::sim::SensorType> type = dlo::sim::parseSensorType(sensor);
  if (!type) {
    throw dlo::UsageError("--sensor must be VLP16, HDL32, HDL64, OS64 or OS128, got '" + sensor +
                          "'.");
  }
  o.sensor = *type;
  if (seed < 0 || seed > 4294967295L) throw dlo::UsageError("--seed must be 0 to 4294967295.");
  if (frames < 30 || frames > 100000) throw dlo::UsageError("--frames must be 30 to 100000.");
  o.seed = static_cast<unsigned>(seed);
  o.frames = static_cast<int>(frames);
  // The grid's own checks (DloParams::validate()), on values that fit their fields.
  if (std::abs(cols) > 1000000 || std::abs(levels) > 1000)
    throw dlo::UsageError("--cols or --centroid-levels is out of range.");
  o.params.grid.cols = o.params.grid.rows = static_cast<int>(cols);
  o.params.selection.centroid_levels = static_cast<int>(levels);
  if (const std::string bad = o.params.validate(); !bad.empty()) throw dlo::UsageError(bad);
  return true;
}

/// Sweep k of the drive, each point placed with the vehicle's pose at its own time and
/// expressed in the vehicle frame at the middle of the sweep; `pose` gets that frame.
dlo::PointCloud undistortedSweep(const dlo::sim::SweepSimulator& simulator,
                                 const dlo::sim::VehicleTrajectory& trajectory, int k,
                                 Eigen::Isometry3d& pose) {
  const dlo::sim::Sweep sweep = simulator.simulate(k);
  pose = trajectory.vehiclePose(static_cast<double>(sweep.referenceTimeNs) * 1e-9 + 0.05);
  const Eigen::Isometry3d to_vehicle = pose.inverse();
  const Eigen::Isometry3d mount = trajectory.sensorMount();
  dlo::PointCloud points;
  for (int f = 0; f < sweep.firings; ++f) {
    for (int l = 0; l < sweep.lasers; ++l) {
      if (sweep.range[sweep.index(f, l)] < 2.0f) continue;  // dlo-slam's --min-range
      const double t = static_cast<double>(simulator.pointTimeNs(sweep, f, l)) * 1e-9;
      const Eigen::Vector3d world =
          trajectory.vehiclePose(t) * (mount * simulator.sensorPoint(sweep, f, l));
      points.push_back((to_vehicle * world).cast<float>());
    }
  }
  return points;
}

struct Bin {
  std::vector<double> along;  ///< metres
  double squared = 0.0;       ///< sum of the squared planar errors
};

/// The measurement; \return the exit status.
int run(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) return 0;
  // The town of dlo-simulate's default drive: laps of its block, corners on 8 m clothoids.
  const dlo::sim::WorldParams town;
  const auto world = dlo::sim::ProceduralWorld::generate(o.seed, town);
  const auto route = dlo::sim::Route::roundedRectangle(town.loopMin, town.loopMax, 10.0, 8.0,
                                                       dlo::sim::SpeedLimits());
  const dlo::sim::VehicleTrajectory trajectory(route, world.terrain());
  dlo::sim::SweepSimulatorParams sp;
  sp.model = dlo::sim::makeLidarModel(o.sensor);
  sp.seed = o.seed;
  const dlo::sim::SweepSimulator simulator(world, trajectory, sp);

  std::vector<dlo::PointCloud> sweeps(static_cast<size_t>(o.frames));
  std::vector<Eigen::Isometry3d> poses(sweeps.size());
  for (int k = 0; k < o.frames; ++k)
    sweeps[k] = undistortedSweep(simulator, trajectory, k, poses[k]);

  const dlo::DloParams& p = o.params;
  const dlo::DirectAligner aligner(p.solver);
  std::map<int, Bin> bins;  // by distance, 0.5 m each
  // From the 20th sweep on (the car is up to speed), each against the next twelve.
  for (int i = 20; i + 1 < o.frames; ++i) {
    const dlo::HeightFrame reference =
        dlo::HeightFrame::fromPoints(sweeps[i], p.grid, p.selection, false);
    for (int k = i + 1; k <= i + 12 && k < o.frames; ++k) {
      const Eigen::Isometry3d truth = poses[i].inverse() * poses[k];
      const double distance = truth.translation().head<2>().norm();
      if (distance < 0.2) continue;
      const dlo::HeightFrame current =
          dlo::HeightFrame::fromPoints(sweeps[k], p.grid, p.selection, false);
      const dlo::AlignmentResult r = aligner.align(reference, current, truth);
      const Eigen::Vector2d error = (r.pose.translation() - truth.translation()).head<2>();
      Bin& bin = bins[static_cast<int>(distance / 0.5)];
      bin.along.push_back(error.dot(truth.translation().head<2>() / distance));
      bin.squared += error.squaredNorm();
    }
  }
  std::printf(
      "| distance m | pairs | median along mm | mean along mm | RMS mm |\n|---|---|---|---|---|\n");
  for (auto& [b, bin] : bins) {
    std::sort(bin.along.begin(), bin.along.end());
    double sum = 0.0;
    for (double a : bin.along) sum += a;
    const double n = static_cast<double>(bin.along.size());
    std::printf("| %.1f-%.1f | %zu | %+.2f | %+.2f | %.1f |\n", 0.5 * b, 0.5 * b + 0.5,
                bin.along.size(), 1000.0 * bin.along[bin.along.size() / 2], 1000.0 * sum / n,
                1000.0 * std::sqrt(bin.squared / n));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo_registration_bias", [&] { return run(argc, argv); });
}
