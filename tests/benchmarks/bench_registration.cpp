// Google Benchmark: DLO registration of the two halves of the real HDL-64 scan, per stage and
// whole, one Gauss-Newton iteration, and a whole odometry step on the real KITTI city drive. Run:
// build/tests/benchmarks/dlo_bench_registration
//   --benchmark_repetitions=10 --benchmark_report_aggregates_only=true
// The current half is the odd points moved by x = 1.0 m, y = -0.5 m, yaw = 5 deg; the
// registration starts from the identity, as with no motion prior.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/sweep_timing.h"
#include "dlo/core/weighted_cloud.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/slam/lidar_odometry.h"

namespace {

struct Halves {
  dlo::PointCloud reference;
  dlo::PointCloud current;
};

const Halves& halves() {
  static const Halves h = [] {
    const dlo::PointCloud scan =
        dlo::loadKittiBin(std::string(DLO_SHARED_DATA_DIR) + "/kitti_00_000000.bin.gz");
    const Eigen::Isometry3f inv =
        dlo::poseFromXYZYPR(1.0, -0.5, 0.0, 5.0 * M_PI / 180.0, 0.0, 0.0).inverse().cast<float>();
    Halves out;
    for (size_t i = 0; i < scan.size(); ++i) {
      if (i % 2 == 0) {
        out.reference.push_back(scan[i]);
      } else {
        out.current.push_back(inv * scan[i]);
      }
    }
    return out;
  }();
  return h;
}

dlo::DloParams paramsFor(int dof) {
  dlo::DloParams p;
  p.solver.dof = dof;
  return p;
}

/// A keyframe's decimation of `points`: into 0.1 m voxels (odometry.keyframe_voxel), then those
/// into 0.2 m voxels (odometry.map_voxel).
void keyframeVoxels(benchmark::State& state, const dlo::PointCloud& points) {
  size_t voxels = 0;
  for (auto _ : state) {
    const dlo::WeightedCloud fine = dlo::voxelise(points, 0.1);
    const dlo::WeightedCloud coarse = dlo::voxelise(fine, 0.2);
    voxels = fine.size();
    benchmark::DoNotOptimize(coarse.data());
  }
  state.counters["points"] = static_cast<double>(points.size());
  state.counters["voxels"] = static_cast<double>(voxels);
}

/// The whole real HDL-64 scan (124,668 points).
void BM_KeyframeVoxels(benchmark::State& state) {
  keyframeVoxels(state,
                 dlo::loadKittiBin(std::string(DLO_SHARED_DATA_DIR) + "/kitti_00_000000.bin.gz"));
}

/// What a keyframe of dlo-slam voxelises: the scan's points within odometry.map_range (40 m).
void BM_KeyframeVoxelsNear(benchmark::State& state) {
  const dlo::PointCloud scan =
      dlo::loadKittiBin(std::string(DLO_SHARED_DATA_DIR) + "/kitti_00_000000.bin.gz");
  dlo::PointCloud near;
  for (const Eigen::Vector3f& p : scan) {
    if (p.head<2>().squaredNorm() <= 40.0f * 40.0f) near.push_back(p);
  }
  keyframeVoxels(state, near);
}

/// Per-point times from the azimuths of the whole real HDL-64 scan (124,668 points), what a
/// scan without times costs before it is deskewed.
void BM_EstimateSweepTimes(benchmark::State& state) {
  const dlo::PointCloud scan =
      dlo::loadKittiBin(std::string(DLO_SHARED_DATA_DIR) + "/kitti_00_000000.bin.gz");
  std::vector<float> times;
  for (auto _ : state) {
    const dlo::SweepTimingEstimate e =
        dlo::estimateSweepTimes(scan, dlo::SweepTimingParams(), times);
    benchmark::DoNotOptimize(e);
    benchmark::DoNotOptimize(times.data());
  }
  state.counters["points"] = static_cast<double>(scan.size());
}

void BM_RasteriseFinestGrid(benchmark::State& state) {
  const dlo::DloParams p;
  const dlo::GridGeometry geo =
      dlo::GridGeometry::centred(p.grid.cols, p.grid.rows, p.grid.resolution);
  dlo::HeightGrid g;
  for (auto _ : state) {
    g.rasterise(halves().current, geo, p.grid.min_points, p.grid.min_z, p.grid.max_z);
    benchmark::DoNotOptimize(g.validCellCount());
  }
  state.counters["points"] = static_cast<double>(halves().current.size());
}

void BM_PyramidAndHoleFilling(benchmark::State& state) {
  const dlo::DloParams p;
  const dlo::GridGeometry geo =
      dlo::GridGeometry::centred(p.grid.cols, p.grid.rows, p.grid.resolution);
  const dlo::HeightGrid finest = dlo::HeightGrid::fromPoints(
      halves().current, geo, p.grid.min_points, p.grid.min_z, p.grid.max_z);
  std::vector<dlo::HeightGrid> levels(static_cast<size_t>(p.grid.levels));
  for (auto _ : state) {
    levels[0] = finest;
    for (int k = 1; k < p.grid.levels; ++k) levels[k].poolFrom(levels[k - 1]);
    for (int k = p.grid.levels - 2; k >= 0; --k) levels[k].fillHolesFrom(levels[k + 1]);
    benchmark::DoNotOptimize(levels.front().heights().data());
  }
}

void BM_Gradients(benchmark::State& state) {
  const dlo::DloParams p;
  const dlo::HeightFrame f =
      dlo::HeightFrame::fromPoints(halves().current, p.grid, p.selection, false);
  dlo::GradientField g;
  for (auto _ : state) {
    for (const dlo::FrameLevel& level : f.levels()) {
      dlo::computeGradients(level.grid, g);
      benchmark::DoNotOptimize(g.cells.data());
    }
  }
}

void BM_Selection(benchmark::State& state) {
  const dlo::DloParams p;
  const dlo::HeightFrame f =
      dlo::HeightFrame::fromPoints(halves().current, p.grid, p.selection, false);
  std::vector<dlo::SelectedCell> cells;
  for (auto _ : state) {
    for (const dlo::FrameLevel& level : f.levels()) {
      dlo::selectHighGradientCells(level.grid, level.sampler.gradients(), p.selection, false,
                                   cells);
      benchmark::DoNotOptimize(cells.data());
    }
  }
  state.counters["cells_finest"] = static_cast<double>(f.levels().front().cells.size());
}

/// The selection of a scan that is never a reference: gradients of measured cells only, the
/// finest level's neighbours pulled from level 1 instead of filled.
void BM_SelectionWithoutGradientField(benchmark::State& state) {
  const dlo::DloParams p;
  dlo::HeightFrame f = dlo::HeightFrame::fromPoints(halves().current, p.grid, p.selection, false);
  std::vector<dlo::HeightGrid> levels;
  for (const dlo::FrameLevel& level : f.levels()) levels.push_back(level.grid);
  // The finest level as a current-only frame leaves it: measured cells only.
  levels[0] = dlo::HeightGrid::fromPoints(
      halves().current, dlo::GridGeometry::centred(p.grid.cols, p.grid.rows, p.grid.resolution),
      p.grid.min_points, p.grid.min_z, p.grid.max_z);
  std::vector<dlo::SelectedCell> cells;
  for (auto _ : state) {
    for (size_t k = 0; k < levels.size(); ++k) {
      dlo::selectHighGradientCells(levels[k], k == 0 ? &levels[1] : nullptr, p.selection, false,
                                   cells);
      benchmark::DoNotOptimize(cells.data());
    }
  }
}

/// A whole frame from raw points: grid, pyramid, gradients, selection.
void BM_BuildFrame(benchmark::State& state) {
  const dlo::DloParams p = paramsFor(static_cast<int>(state.range(0)));
  dlo::StageTimes sum;
  dlo::HeightFrame f;  // rebuilt in place, as the odometry does for every scan
  for (auto _ : state) {
    f.build(halves().current, p.grid, p.selection, p.includeGround());
    sum += f.buildTimes();
    benchmark::DoNotOptimize(f.levels().data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["grid_ms"] = sum.grid_ms / n;
  state.counters["gradients_ms"] = sum.gradients_ms / n;
  state.counters["selection_ms"] = sum.selection_ms / n;
}

/// A frame as the odometry builds each scan against a local map: deskewed while rasterised
/// (a constant-velocity sweep of 10 m/s and 20 deg/s over 0.1 s), current-only.
void BM_BuildCurrentFrame(benchmark::State& state) {
  const dlo::DloParams p = paramsFor(static_cast<int>(state.range(0)));
  const dlo::PointCloud& points = halves().current;
  std::vector<float> times(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    times[i] = -0.1f + 0.1f * static_cast<float>(i) / static_cast<float>(points.size());
  dlo::Vector6d velocity;
  velocity << 10.0, 0.0, 0.0, 0.0, 0.0, 20.0 * M_PI / 180.0;
  dlo::StageTimes sum;
  dlo::HeightFrame f;
  for (auto _ : state) {
    const dlo::SweepMotion motion(times, velocity);
    f.build(points, motion, p.grid, p.selection, p.includeGround(), dlo::FrameUse::kCurrentOnly);
    sum += f.buildTimes();
    benchmark::DoNotOptimize(f.levels().data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["grid_ms"] = sum.grid_ms / n;
  state.counters["selection_ms"] = sum.selection_ms / n;
}

/// Gauss-Newton alone, coarse to fine, on prebuilt frames.
void BM_GaussNewton(benchmark::State& state) {
  const dlo::DloParams p = paramsFor(static_cast<int>(state.range(0)));
  const dlo::HeightFrame ref =
      dlo::HeightFrame::fromPoints(halves().reference, p.grid, p.selection, p.includeGround());
  const dlo::HeightFrame cur =
      dlo::HeightFrame::fromPoints(halves().current, p.grid, p.selection, p.includeGround());
  const dlo::DirectAligner aligner(p.solver);
  dlo::AlignmentResult r;
  for (auto _ : state) {
    r = aligner.align(ref, cur, Eigen::Isometry3d::Identity());
    benchmark::DoNotOptimize(r.pose.data());
  }
  state.counters["iterations"] = r.iterations;
  state.counters["cells"] = r.cells;
}

/// The whole pair: both frames from raw points, then registration.
void BM_WholePair(benchmark::State& state) {
  const dlo::DloParams p = paramsFor(static_cast<int>(state.range(0)));
  const dlo::DirectAligner aligner(p.solver);
  dlo::HeightFrame ref, cur;  // rebuilt in place, as the odometry does for every scan
  for (auto _ : state) {
    ref.build(halves().reference, p.grid, p.selection, p.includeGround());
    cur.build(halves().current, p.grid, p.selection, p.includeGround());
    const dlo::AlignmentResult r = aligner.align(ref, cur, Eigen::Isometry3d::Identity());
    benchmark::DoNotOptimize(r.pose.data());
  }
}

/// One Gauss-Newton iteration on each of the 4 pyramid levels (max_iterations = 1); the aligner
/// also evaluates the final statistics and covariance once, so this is 4 linearise-and-solve
/// steps plus one linearisation of the finest level: divide by about 5 for one iteration.
void BM_GaussNewtonIteration(benchmark::State& state) {
  dlo::DloParams p = paramsFor(static_cast<int>(state.range(0)));
  p.solver.max_iterations = 1;
  const dlo::HeightFrame ref =
      dlo::HeightFrame::fromPoints(halves().reference, p.grid, p.selection, p.includeGround());
  const dlo::HeightFrame cur =
      dlo::HeightFrame::fromPoints(halves().current, p.grid, p.selection, p.includeGround());
  const dlo::DirectAligner aligner(p.solver);
  // Start near the solution, where the fine level works.
  const Eigen::Isometry3d guess =
      dlo::poseFromXYZYPR(0.95, -0.45, 0.0, 4.8 * M_PI / 180.0, 0.0, 0.0);
  for (auto _ : state) {
    const dlo::AlignmentResult r = aligner.align(ref, cur, guess);
    benchmark::DoNotOptimize(r.pose.data());
  }
  state.counters["cells"] = static_cast<double>(cur.levels().front().cells.size());
}

/// A whole odometry step (deskew skipped: KITTI files carry no per-point times; local-map
/// reference, keyframe decisions) over the 22 real HDL-64 sweeps of kitti_city_seq, cycling.
void BM_OdometryStep(benchmark::State& state) {
  static const std::vector<dlo::PointCloud> scans = [] {
    std::vector<dlo::PointCloud> out;
    for (int i = 0; i < 22; ++i) {
      char name[64];
      std::snprintf(name, sizeof name, "/kitti_city_seq/%06d.bin.gz", i);
      out.push_back(dlo::loadKittiBin(std::string(DLO_SHARED_DATA_DIR) + name));
    }
    return out;
  }();
  const dlo::SlamParams params;
  auto odometry = std::make_unique<dlo::LidarOdometry>(params);
  size_t k = 0;
  for (auto _ : state) {
    if (k == scans.size()) {
      state.PauseTiming();
      odometry = std::make_unique<dlo::LidarOdometry>(params);
      k = 0;
      state.ResumeTiming();
    }
    const dlo::OdometryStep step = odometry->process(0.1 * static_cast<double>(k), scans[k], {});
    benchmark::DoNotOptimize(step.pose.data());
    ++k;
  }
}

}  // namespace

BENCHMARK(BM_GaussNewtonIteration)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_OdometryStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RasteriseFinestGrid)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EstimateSweepTimes)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KeyframeVoxels)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_KeyframeVoxelsNear)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PyramidAndHoleFilling)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Gradients)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Selection)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SelectionWithoutGradientField)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildFrame)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BuildCurrentFrame)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GaussNewton)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_WholePair)->Arg(3)->Arg(6)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
