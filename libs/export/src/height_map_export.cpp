#include "dlo/export/height_map_export.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "dlo/export/atomic_file.h"

namespace dlo {

mrpt::maps::CHeightGridMap2D toHeightGridMap(const WeightedCloud& world_points, double resolution,
                                             double margin) {
  double x_min = std::numeric_limits<double>::infinity(), y_min = x_min;
  double x_max = -x_min, y_max = -x_min;
  for (const WeightedPoint& wp : world_points) {
    x_min = std::min<double>(x_min, wp.p.x());
    x_max = std::max<double>(x_max, wp.p.x());
    y_min = std::min<double>(y_min, wp.p.y());
    y_max = std::max<double>(y_max, wp.p.y());
  }
  if (world_points.empty()) x_min = x_max = y_min = y_max = 0.0;
  mrpt::maps::CHeightGridMap2D grid(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, x_min - margin,
                                    x_max + margin, y_min - margin, y_max + margin, resolution);

  // Sums in double: a cell can gather thousands of points, float sums of z^2 would drift.
  const size_t cells = grid.getSizeX() * grid.getSizeY();
  std::vector<double> sum(cells, 0.0), sum_sq(cells, 0.0);
  std::vector<std::uint64_t> count(cells, 0);
  for (const WeightedPoint& wp : world_points) {
    const int cx = grid.x2idx(wp.p.x()), cy = grid.y2idx(wp.p.y());
    if (cx < 0 || cy < 0 || cx >= static_cast<int>(grid.getSizeX()) ||
        cy >= static_cast<int>(grid.getSizeY())) {
      continue;
    }
    const size_t i = static_cast<size_t>(cy) * grid.getSizeX() + static_cast<size_t>(cx);
    const double n = wp.n, z = wp.p.z();
    sum[i] += n * z;
    sum_sq[i] += n * z * z;
    count[i] += wp.n;
  }
  for (size_t cy = 0; cy < grid.getSizeY(); ++cy) {
    for (size_t cx = 0; cx < grid.getSizeX(); ++cx) {
      const size_t i = cy * grid.getSizeX() + cx;
      if (count[i] == 0) continue;
      mrpt::maps::THeightGridmapCell* cell = grid.cellByIndex(cx, cy);
      const double w = static_cast<double>(count[i]);
      cell->w = static_cast<std::uint32_t>(std::min<std::uint64_t>(count[i], UINT32_MAX));
      cell->u = static_cast<float>(sum[i]);
      cell->v = static_cast<float>(sum_sq[i]);
      cell->h = static_cast<float>(sum[i] / w);
      cell->var =
          w > 1 ? static_cast<float>(std::max(0.0, (sum_sq[i] - sum[i] * sum[i] / w) / (w - 1)))
                : 0.0f;
    }
  }
  return grid;
}

void exportHeightGridMap(const mrpt::maps::CHeightGridMap2D& grid, const std::string& path) {
  writeAtomically(path, [&](const std::string& temp) {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(temp)) throw std::runtime_error("cannot create '" + temp + "'");
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << grid;
    out.close();
  });
}

}  // namespace dlo
