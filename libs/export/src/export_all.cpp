#include "dlo/export/export_all.h"

#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>

#include "dlo/export/height_map_export.h"
#include "dlo/export/ply_export.h"
#include "dlo/export/pose_graph_export.h"
#include "dlo/export/simple_map_export.h"
#include "dlo/export/trajectory_export.h"
#include "dlo/export/world_cloud.h"
#include "dlo/files/atomic_file.h"
#include "dlo/formats/png_file.h"

namespace dlo {

namespace fs = std::filesystem;

namespace {

/// Fails early, before any export, when `dir` cannot receive files.
void checkWritableFolder(const std::string& dir) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    throw OutputError("cannot export into '" + dir + "' (it is not an existing folder).");
  }
  const fs::path probe = fs::path(dir) / ".dlo_export_probe.tmp";
  bool ok = static_cast<bool>(std::ofstream(probe));
  fs::remove(probe, ec);
  if (!ok) throw OutputError("cannot export into '" + dir + "' (the folder is not writable).");
}

}  // namespace

ExportReport exportAll(const SlamMap& map, const std::string& dir, const ExportOptions& options) {
  checkWritableFolder(dir);
  ExportReport report;
  auto run = [&](const std::string& name, const std::function<void(const std::string&)>& write) {
    const std::string path = (fs::path(dir) / name).string();
    try {
      write(path);
      report.written.push_back(path);
    } catch (const std::exception& e) {
      report.warnings.push_back(e.what());
    }
  };

  run("trajectory.tum", [&](const std::string& p) { exportTrajectoryTum(map, p); });
  run("trajectory.kitti", [&](const std::string& p) { exportTrajectoryKitti(map, p); });
  run("keyframes.graph", [&](const std::string& p) { exportPoseGraph(map, p); });
  run("map.simplemap", [&](const std::string& p) { exportSimpleMap(map, p); });

  // The height grid needs every point, not the decimated map: mean heights stay exact. Both it
  // and the map cloud are fed one keyframe at a time (bounds first, then sums and voxels), so a
  // long run's export holds one keyframe cloud and the merged voxels, not every keyframe.
  HeightGridAccumulator heights(options.heightmap_resolution, options.heightmap_margin);
  // The occupancy grid takes the same passes: bounds, each cell's lowest point, then (a third)
  // what rises above the ground.
  OccupancyGridAccumulator occupancy(options.occupancy);
  forEachWorldCloud(map, [&](const WeightedCloud& c) {
    heights.extend(c);
    occupancy.extend(c);
  });
  std::optional<VoxelMerger> voxels;
  if (options.map_voxel > 0.0) voxels.emplace(options.map_voxel);
  WeightedCloud cloud;  // undecimated map when map_voxel <= 0
  forEachWorldCloud(map, [&](const WeightedCloud& c) {
    heights.add(c);
    occupancy.ground(c);
    if (voxels) {
      voxels->add(c);
    } else {
      cloud.insert(cloud.end(), c.begin(), c.end());
    }
  });
  if (voxels) cloud = voxels->result();
  voxels.reset();
  const mrpt::maps::CHeightGridMap2D grid = heights.grid();
  run("heightmap.bin", [&](const std::string& p) { exportHeightGridMap(grid, p); });
  run("heightmap_centroids.bin",
      [&](const std::string& p) { writeHeightMapCentroids(heights.centroids(), p); });
  run("heightmap.png",
      [&](const std::string& p) { writePng(renderHeightMapImage(grid, map, options.image), p); });

  forEachWorldCloud(map, [&](const WeightedCloud& c) { occupancy.classify(c); });
  try {
    for (const std::string& p :
         exportOccupancyGrid(occupancy.grid(), (fs::path(dir) / "map").string()))
      report.written.push_back(p);
  } catch (const std::exception& e) {
    report.warnings.push_back(e.what());
  }

  run("map.ply", [&](const std::string& p) { exportPly(cloud, p); });
  const auto scene = buildMapScene(map, cloud, options.scene);
  run("map.3Dscene", [&](const std::string& p) { exportScene(*scene, p); });
  if (options.render) {
    run("map_render.png", [&](const std::string& p) { renderScenePng(*scene, p, options.scene); });
  }
  return report;
}

}  // namespace dlo
