// loadPriorMap() on folders that are not a dlo-slam map: one InputError naming the file; the
// height map's heights moved from their centroids to their cells' centres. The Localizer itself
// is tested on simulated drives in test_slam_loop.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "../temp_dir.h"
#include "dlo/export/export_all.h"
#include "dlo/export/simple_map_export.h"
#include "dlo/files/error.h"
#include "dlo/formats/height_map_centroids.h"
#include "dlo/slam/localizer.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

/// The message of the InputError that loadPriorMap(dir) throws, or "" if it throws none.
std::string loadError(const fs::path& dir) {
  try {
    loadPriorMap(dir.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

class PriorMapFolder : public ::testing::Test {
 protected:
  test::TempDir tmp_;
  const fs::path& dir_ = tmp_.dir();
};

TEST_F(PriorMapFolder, AFolderWithoutAMapNamesMapSimplemap) {
  const std::string message = loadError(dir_);
  EXPECT_NE(message.find("map.simplemap"), std::string::npos) << message;
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;
}

TEST_F(PriorMapFolder, ACorruptSimplemapIsNamed) {
  std::ofstream(dir_ / "map.simplemap") << "not a simplemap";
  const std::string message = loadError(dir_);
  EXPECT_NE(message.find("map.simplemap"), std::string::npos) << message;
  EXPECT_NE(message.find("not a readable CSimpleMap"), std::string::npos) << message;
}

TEST_F(PriorMapFolder, KeyframesWithoutAHeightMapNameHeightmapBin) {
  // One keyframe with a few points, written as dlo-slam writes it.
  SlamMap map;
  Keyframe kf;
  kf.pose = Eigen::Isometry3d::Identity();
  map.keyframes.push_back(kf);
  map.keyframes[0].cloud = {WeightedPoint{Eigen::Vector3f(1.0f, 2.0f, 0.0f), 1u},
                            WeightedPoint{Eigen::Vector3f(3.0f, 2.0f, 1.0f), 1u}};
  exportSimpleMap(map, (dir_ / "map.simplemap").string());
  std::string message = loadError(dir_);
  EXPECT_NE(message.find("heightmap.bin"), std::string::npos) << message;
  std::ofstream(dir_ / "heightmap.bin") << "corrupt";
  message = loadError(dir_);
  EXPECT_NE(message.find("heightmap.bin"), std::string::npos) << message;
}

/// A 6 x 5 map of 0.2 m cells on the plane z = 0.5 x - 0.25 y + 1 (cell (ix, iy) has its centre
/// at (0.2 ix + 0.1, 0.2 iy + 0.1)), each cell's mean height measured at its centroid `places`,
/// except the cells of `empty`.
PriorMap planeMeasuredAtCentroids(const std::vector<std::uint8_t>& places,
                                  const std::vector<size_t>& empty) {
  PriorMap map;
  map.resolution = 0.2;
  map.cols = 6;
  map.rows = 5;
  map.count.assign(30, 0);
  map.sum.assign(30, 0.0f);
  for (int iy = 0; iy < map.rows; ++iy) {
    for (int ix = 0; ix < map.cols; ++ix) {
      const size_t k = static_cast<size_t>(iy * map.cols + ix);
      if (std::find(empty.begin(), empty.end(), k) != empty.end()) continue;
      const double x = 0.2 * (ix + HeightMapCentroids::fraction(places[2 * k]));
      const double y = 0.2 * (iy + HeightMapCentroids::fraction(places[2 * k + 1]));
      map.count[k] = 4;
      map.sum[k] = static_cast<float>(4.0 * (0.5 * x - 0.25 * y + 1.0));
    }
  }
  return map;
}

TEST(CentreHeights, MovesAPlanesHeightsToTheCellCentres) {
  // Every cell sampled on the same side (a sensor to the south-west), the slope across the map
  // is exact between the cells; two empty cells, one of them in a corner, leave one-sided
  // slopes beside them.
  std::vector<std::uint8_t> places(60);
  for (size_t i = 0; i < places.size(); i += 2) {
    places[i] = 40;
    places[i + 1] = 220;
  }
  PriorMap map = planeMeasuredAtCentroids(places, {0, 14});
  map.centroids = places;
  EXPECT_GT(std::abs(map.sum[7] / map.count[7] - (0.5 * 0.3 - 0.25 * 0.3 + 1.0)), 0.02);
  centreHeights(map);
  EXPECT_TRUE(map.heights_at_centres);
  for (int iy = 0; iy < map.rows; ++iy) {
    for (int ix = 0; ix < map.cols; ++ix) {
      const size_t k = static_cast<size_t>(iy * map.cols + ix);
      if (map.count[k] == 0) continue;
      const double expected = 0.5 * (0.2 * ix + 0.1) - 0.25 * (0.2 * iy + 0.1) + 1.0;
      EXPECT_NEAR(map.sum[k] / map.count[k], expected, 1e-5) << "cell " << ix << ", " << iy;
    }
  }
  EXPECT_EQ(map.count[0], 0u);
  EXPECT_EQ(map.count[14], 0u);
}

TEST(CentreHeights, ACellWithNoMeasuredNeighbourKeepsItsHeight) {
  std::vector<std::uint8_t> places(60, 200);
  // Only cell 8 (ix 2, iy 1) is measured.
  std::vector<size_t> empty;
  for (size_t k = 0; k < 30; ++k) {
    if (k != 8) empty.push_back(k);
  }
  PriorMap map = planeMeasuredAtCentroids(places, empty);
  map.centroids = places;
  const float before = map.sum[8];
  centreHeights(map);
  EXPECT_EQ(map.sum[8], before);
  map.centroids.pop_back();
  EXPECT_THROW(centreHeights(map), std::invalid_argument);
}

TEST_F(PriorMapFolder, CentroidsOfAnotherGridAreNamed) {
  SlamMap map;
  Keyframe kf;
  kf.pose = Eigen::Isometry3d::Identity();
  map.keyframes.push_back(kf);
  for (int i = 0; i < 50; ++i) {
    map.keyframes[0].cloud.push_back(WeightedPoint{Eigen::Vector3f(0.1f * i, 0.05f * i, 0.0f), 1u});
  }
  ExportOptions options;
  options.render = false;
  exportAll(map, dir_.string(), options);
  // As dlo-slam wrote it, the map loads with its centroids, its heights moved to the cells'
  // centres by a localiser whose profile places a scan's cells at their centroids (the dense
  // one), and left where they are otherwise; a map made before the centroids were written loads
  // without them, its heights where they are.
  PriorMap loaded = loadPriorMap(dir_.string());
  EXPECT_EQ(loaded.centroids.size(), 2u * loaded.count.size());
  EXPECT_FALSE(loaded.heights_at_centres);
  SlamParams dense;
  dense.registration.selection.centroid_levels = 2;
  EXPECT_TRUE(Localizer(loaded, LocalizerParams(), dense).map().heights_at_centres);
  SlamParams sparse;
  sparse.registration.selection.centroid_levels = 0;
  EXPECT_FALSE(Localizer(loaded, LocalizerParams(), sparse).map().heights_at_centres);
  fs::remove(dir_ / "heightmap_centroids.bin");
  loaded = loadPriorMap(dir_.string());
  EXPECT_TRUE(loaded.centroids.empty());
  EXPECT_FALSE(Localizer(loaded, LocalizerParams(), dense).map().heights_at_centres);
  HeightMapCentroids other;
  other.cols = 3;
  other.rows = 3;
  other.places.assign(18, 128);
  writeHeightMapCentroids(other, (dir_ / "heightmap_centroids.bin").string());
  std::string message = loadError(dir_);
  EXPECT_NE(message.find("heightmap_centroids.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("3 x 3"), std::string::npos) << message;
  std::ofstream(dir_ / "heightmap_centroids.bin") << "corrupt";
  message = loadError(dir_);
  EXPECT_NE(message.find("heightmap_centroids.bin"), std::string::npos) << message;
}

}  // namespace
}  // namespace dlo
