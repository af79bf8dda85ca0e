/// \file export_all.h
/// \brief Every export of a SLAM run into one folder.
#pragma once

#include <string>
#include <vector>

#include "dlo/export/height_map_image.h"
#include "dlo/export/occupancy_grid_export.h"
#include "dlo/export/scene_export.h"
#include "dlo/slam/slam_map.h"

namespace dlo {

/// What exportAll() writes and how.
struct ExportOptions {
  double heightmap_resolution = 0.2;  ///< metres per cell of heightmap.bin / heightmap.png
  double heightmap_margin = 2.0;      ///< metres added around the points' x-y bounds
  double map_voxel = 0.2;             ///< metres; voxel of map.ply and the points of map.3Dscene
  bool render = true;                 ///< also render map_render.png (needs EGL)
  HeightMapImageOptions image;        ///< heightmap.png
  OccupancyGridOptions occupancy;     ///< map.gridmap, map.png, map.yaml
  SceneOptions scene;                 ///< map.3Dscene and map_render.png
};

/// The outcome of exportAll(): files written (full paths) and one sentence per file that failed.
struct ExportReport {
  std::vector<std::string> written;
  std::vector<std::string> warnings;
};

/// Writes into the existing folder `dir`: trajectory.tum, trajectory.kitti, keyframes.graph,
/// map.simplemap, heightmap.bin, heightmap.png, the occupancy grid (map.gridmap, map.png,
/// map.yaml: exportOccupancyGrid()), map.ply, map.3Dscene and (with options.render)
/// map_render.png. Each file is written atomically; a file that fails (e.g. rendering without
/// EGL) becomes a warning and does not prevent the others.
/// \throws OutputError naming `dir` if it does not exist or is not writable (nothing is written).
ExportReport exportAll(const SlamMap& map, const std::string& dir,
                       const ExportOptions& options = ExportOptions());

}  // namespace dlo
