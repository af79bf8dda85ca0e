#include "dlo/bench/classic_preprocessing.h"

#include <cstdio>

#include "dlo/core/deskew.h"
#include "dlo/core/weighted_cloud.h"

namespace dlo::bench {

std::string ClassicPreprocessing::describe() const {
  char text[96];
  std::snprintf(text, sizeof text, "%scrop %.0f m, voxel %.2f m", deskew ? "deskew, " : "",
                max_range, voxel);
  return text;
}

PointCloud preprocessScan(const PointCloud& points, const std::vector<float>& point_times,
                          const Vector6d& velocity, const ClassicPreprocessing& options) {
  const bool deskew = options.deskew && point_times.size() == points.size();
  const PointCloud straight = deskew ? dlo::deskew(points, point_times, velocity) : PointCloud();
  const PointCloud& source = deskew ? straight : points;
  const float r2 = static_cast<float>(options.max_range * options.max_range);
  PointCloud cropped;
  cropped.reserve(source.size());
  for (const auto& p : source) {
    if (p.squaredNorm() <= r2) cropped.push_back(p);
  }
  const WeightedCloud voxels = voxelise(cropped, options.voxel);
  PointCloud out;
  out.reserve(voxels.size());
  for (const WeightedPoint& v : voxels) out.push_back(v.p);
  return out;
}

}  // namespace dlo::bench
