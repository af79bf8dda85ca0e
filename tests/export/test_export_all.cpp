// exportAll() on a synthetic map, and every output loaded back with the reader its users have.
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "../temp_dir.h"
#include "dlo/export/export_all.h"
#include "dlo/export/height_map_export.h"
#include "dlo/formats/height_map_centroids.h"
#include "dlo/formats/ply_file.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/pose_conversion.h"
#include "synthetic_map.h"

namespace fs = std::filesystem;
using dlo::test::SyntheticWorld;

namespace {

/// The lowest and highest free probability of the cells within one cell of (x, y): points on
/// the synthetic lattices fall on cell borders.
std::pair<float, float> around(const mrpt::maps::COccupancyGridMap2D& g, double x, double y) {
  float lo = 1.0f, hi = 0.0f;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const float v = g.getPos(x + dx * g.getResolution(), y + dy * g.getResolution());
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  return {lo, hi};
}

/// One export of the synthetic map shared by all tests of the suite (it is the slow part).
class ExportAll : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    map_ = new dlo::SlamMap(dlo::test::makeSyntheticMap());
    folder_ = new dlo::test::TempDir("all");
    report_ = new dlo::ExportReport(dlo::exportAll(*map_, folder_->dir().string()));
  }
  static void TearDownTestSuite() {
    delete report_;
    delete folder_;
    delete map_;
  }
  static std::string file(const std::string& name) { return folder_->path(name); }
  /// The warning about `name`, or "" if it was written.
  static std::string warningAbout(const std::string& name) {
    for (const std::string& w : report_->warnings) {
      if (w.find(name) != std::string::npos) return w;
    }
    return "";
  }

  static dlo::SlamMap* map_;
  static dlo::test::TempDir* folder_;
  static dlo::ExportReport* report_;
};

dlo::SlamMap* ExportAll::map_ = nullptr;
dlo::test::TempDir* ExportAll::folder_ = nullptr;
dlo::ExportReport* ExportAll::report_ = nullptr;

/// Output of a shell command and its exit status.
std::pair<std::string, int> run(const std::string& command) {
  std::string out;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return {"", -1};
  std::array<char, 256> buf;
  while (std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  return {out, ::pclose(pipe)};
}

}  // namespace

TEST_F(ExportAll, WritesEveryFileAndNoTemporaryOnes) {
  for (const std::string& w : report_->warnings) ADD_FAILURE_AT(__FILE__, __LINE__) << w;
  for (const char* name : {"trajectory.tum", "trajectory.kitti", "keyframes.graph", "map.simplemap",
                           "heightmap.bin", "heightmap_centroids.bin", "heightmap.png",
                           "map.gridmap", "map.png", "map.yaml", "map.ply", "map.3Dscene"}) {
    EXPECT_TRUE(fs::is_regular_file(file(name))) << name;
    EXPECT_NE(std::find(report_->written.begin(), report_->written.end(), file(name)),
              report_->written.end())
        << name;
  }
  for (const auto& entry : fs::directory_iterator(folder_->dir())) {
    EXPECT_NE(entry.path().extension(), ".tmp") << entry.path();
  }
}

TEST_F(ExportAll, TrajectoriesReadBackAsTheFramePoses) {
  const auto tum = dlo::metrics::readTumTrajectory(file("trajectory.tum"));
  const auto kitti = dlo::metrics::readKittiTrajectory(file("trajectory.kitti"));
  ASSERT_EQ(tum.size(), map_->frames.size());
  ASSERT_EQ(kitti.size(), map_->frames.size());
  EXPECT_TRUE(tum.poses[0].isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  for (size_t i = 0; i < tum.size(); ++i) {
    EXPECT_TRUE(tum.poses[i].isApprox(map_->framePose(i), 1e-7)) << i;
    EXPECT_TRUE(kitti.poses[i].isApprox(map_->framePose(i), 1e-7)) << i;
    EXPECT_NEAR(tum.times[i], map_->frames[i].time, 1e-9);
  }
}

TEST_F(ExportAll, PoseGraphLoadsWithNodesEdgesAndInformationOrder) {
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  graph.loadFromTextFile(file("keyframes.graph"));
  EXPECT_EQ(graph.nodes.size(), map_->keyframes.size());
  EXPECT_EQ(graph.edges.size(), map_->edges.size());
  const auto pose3 = dlo::toIsometry(graph.nodes.at(3));
  EXPECT_TRUE(pose3.isApprox(map_->keyframes[3].pose, 1e-8));
  // The loop edge 9 -> 0 keeps x y z yaw pitch roll information in MRPT's order, through the
  // file's roll-pitch-yaw layout.
  const auto loop = graph.edges.find({9, 0});
  ASSERT_NE(loop, graph.edges.end());
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(loop->second.cov_inv(i, i), 100.0 * (i + 1), 1e-9);
  EXPECT_TRUE(dlo::toIsometry(loop->second.mean).isApprox(map_->edges.back().relative, 1e-8));
}

TEST_F(ExportAll, GraphSlamToolReadsThePoseGraph) {
  if (!fs::exists("/usr/bin/graph-slam")) GTEST_SKIP() << "graph-slam (apt mrpt-apps) missing";
  const auto [out, status] = run("/usr/bin/graph-slam --info --3d -i " + file("keyframes.graph"));
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("Edge count                         : 10"), std::string::npos) << out;
  EXPECT_NE(out.find("Nodes count (in VERTEX2/3 entries) : 10"), std::string::npos) << out;
}

TEST_F(ExportAll, SimpleMapHoldsOnePointCloudPerKeyframe) {
  mrpt::maps::CSimpleMap simple;
  ASSERT_TRUE(simple.loadFromFile(file("map.simplemap")));
  ASSERT_EQ(simple.size(), map_->keyframes.size());
  for (size_t k = 0; k < simple.size(); ++k) {
    const auto [pdf, frame] = simple.get(k);
    mrpt::poses::CPose3D mean;
    pdf->getMean(mean);
    EXPECT_TRUE(dlo::toIsometry(mean).isApprox(map_->keyframes[k].pose, 1e-8)) << k;
    const auto obs = frame->getObservationByClass<mrpt::obs::CObservationPointCloud>();
    ASSERT_TRUE(obs) << k;
    ASSERT_TRUE(obs->pointcloud);
    EXPECT_EQ(obs->pointcloud->size(), map_->keyframes[k].cloud.size());
    EXPECT_NEAR(mrpt::Clock::toDouble(obs->timestamp), map_->keyframes[k].time, 1e-6);
  }
}

TEST_F(ExportAll, HeightGridHasTheBoxAndTheGround) {
  mrpt::io::CFileGZInputStream in(file("heightmap.bin"));
  mrpt::maps::CHeightGridMap2D grid;
  mrpt::serialization::archiveFrom(in) >> grid;
  EXPECT_NEAR(grid.getResolution(), 0.2, 1e-9);
  double z = -1;
  ASSERT_TRUE(grid.dem_get_z(SyntheticWorld::kBoxX + 0.5, SyntheticWorld::kBoxY - 0.7, z));
  EXPECT_NEAR(z, SyntheticWorld::kBoxHeight, 1e-4);
  // A ground cell next to keyframe 0 (at the origin); the ground lattice is 0.4 m, so pick a
  // cell centred on a lattice point.
  const auto* ground = grid.cellByPos(0.0, -4.0);
  ASSERT_NE(ground, nullptr);
  EXPECT_GT(ground->w, 0u);
  EXPECT_NEAR(ground->h, 0.0, 1e-4);
  // The grid covers every point plus the margin: the far side of the circle (y = 30 m) and the
  // 20 m range around it.
  EXPECT_GE(grid.getYMax(), 2 * SyntheticWorld::kRadius + 20.0);
}

TEST_F(ExportAll, HeightMapCentroidsMatchTheHeightGrid) {
  mrpt::io::CFileGZInputStream in(file("heightmap.bin"));
  mrpt::maps::CHeightGridMap2D grid;
  mrpt::serialization::archiveFrom(in) >> grid;
  const dlo::HeightMapCentroids c = dlo::readHeightMapCentroids(file("heightmap_centroids.bin"));
  EXPECT_EQ(c.cols, grid.getSizeX());
  EXPECT_EQ(c.rows, grid.getSizeY());
  EXPECT_EQ(c.places.size(), 2 * grid.getSizeX() * grid.getSizeY());
}

TEST(HeightGridAccumulator, CentroidsAreWhereTheWeightedPointsLie) {
  // A 0.5 m grid from (-1, -1) (the lowest point, no margin). Its cell (2, 2) spans [0, 0.5) x
  // [0, 0.5): one point at (0.1, 0.4) counted three times and one at (0.3, 0.2) put its
  // centroid at (0.15, 0.35), 0.3 and 0.7 of the cell. Cell (3, 2) holds one point at its
  // centre; cell (3, 3) holds none (the centre).
  const auto point = [](float x, float y, std::uint32_t n) {
    return dlo::WeightedPoint{Eigen::Vector3f(x, y, 0.0f), n};
  };
  const dlo::WeightedCloud points = {point(-1.0f, -1.0f, 1), point(1.9f, 1.9f, 1),
                                     point(0.1f, 0.4f, 3),   point(0.3f, 0.2f, 1),
                                     point(0.75f, 0.25f, 1), point(0.2f, 0.9f, 1)};
  dlo::HeightGridAccumulator acc(0.5, 0.0);
  acc.extend(points);
  acc.add(points);
  const mrpt::maps::CHeightGridMap2D grid = acc.grid();
  ASSERT_NEAR(grid.getXMin(), -1.0, 1e-9);
  ASSERT_NEAR(grid.getYMin(), -1.0, 1e-9);
  const dlo::HeightMapCentroids c = acc.centroids();
  ASSERT_EQ(c.cols, grid.getSizeX());
  ASSERT_EQ(c.rows, grid.getSizeY());
  ASSERT_GE(c.cols, 4u);
  ASSERT_GE(c.rows, 4u);
  ASSERT_EQ(grid.cellByIndex(2, 2)->w, 4u);
  const auto place = [&](size_t cx, size_t cy, int axis) {
    return dlo::HeightMapCentroids::fraction(c.places[2 * (cy * c.cols + cx) + axis]);
  };
  const float step = 1.0f / 256.0f;
  EXPECT_NEAR(place(2, 2, 0), 0.3f, step);
  EXPECT_NEAR(place(2, 2, 1), 0.7f, step);
  EXPECT_NEAR(place(3, 2, 0), 0.5f, step);
  EXPECT_NEAR(place(3, 2, 1), 0.5f, step);
  EXPECT_EQ(grid.cellByIndex(3, 3)->w, 0u);
  EXPECT_NEAR(place(3, 3, 0), 0.5f, step);
  EXPECT_NEAR(place(3, 3, 1), 0.5f, step);
}

TEST_F(ExportAll, OccupancyGridHasTheBoxAsObstacleAndTheGroundFree) {
  mrpt::io::CFileGZInputStream in(file("map.gridmap"));
  mrpt::maps::COccupancyGridMap2D grid;
  mrpt::serialization::archiveFrom(in) >> grid;
  EXPECT_NEAR(grid.getResolution(), 0.2, 1e-6);
  // The box's near face (y = kBoxY - kBoxHalfSide) rises 2 m above the ground beside it.
  const double face_y = SyntheticWorld::kBoxY - SyntheticWorld::kBoxHalfSide + 0.05;
  EXPECT_LT(around(grid, SyntheticWorld::kBoxX, face_y).first, 0.2f);
  EXPECT_LT(around(grid, SyntheticWorld::kBoxX + SyntheticWorld::kBoxHalfSide - 0.05,
                   SyntheticWorld::kBoxY)
                .first,
            0.2f);
  // Ground next to keyframe 0, on the 0.4 m lattice of ground points: free, and nothing near
  // it an obstacle.
  EXPECT_GT(around(grid, 0.0, -4.0).second, 0.8f);
  EXPECT_GT(around(grid, 0.0, -4.0).first, 0.4f);
  // Beyond the points (inside the margin), nothing was seen: unknown.
  EXPECT_NEAR(grid.getPos(grid.getXMin() + 0.1, grid.getYMin() + 0.1), 0.5f, 0.01f);
}

TEST_F(ExportAll, OccupancyGridImageAndYamlDescribeTheSameGrid) {
  mrpt::io::CFileGZInputStream in(file("map.gridmap"));
  mrpt::maps::COccupancyGridMap2D grid;
  mrpt::serialization::archiveFrom(in) >> grid;
  const cv::Mat image = cv::imread(file("map.png"), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty());
  ASSERT_EQ(image.cols, static_cast<int>(grid.getSizeX()));
  ASSERT_EQ(image.rows, static_cast<int>(grid.getSizeY()));
  // Row 0 is the largest y (map_server's convention): the box face is black there.
  // Every cell of the image is the grid's cell, black where occupied.
  int mismatched = 0, black = 0;
  for (int cy = 0; cy < image.rows; ++cy) {
    for (int cx = 0; cx < image.cols; ++cx) {
      const bool occupied = grid.getCell(cx, cy) < 0.35f;
      const bool is_black = image.at<std::uint8_t>(image.rows - 1 - cy, cx) == 0;
      mismatched += occupied != is_black;
      black += is_black;
    }
  }
  EXPECT_EQ(mismatched, 0);
  EXPECT_GT(black, 40) << "the box's faces";
  EXPECT_EQ(image.at<std::uint8_t>(0, 0), 205);  // unknown corner
  std::ifstream yaml(file("map.yaml"));
  std::stringstream text;
  text << yaml.rdbuf();
  EXPECT_NE(text.str().find("image: map.png\n"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("resolution: 0.200000\n"), std::string::npos) << text.str();
  char origin[128];
  std::snprintf(origin, sizeof(origin), "origin: [%.6f, %.6f, 0.0]",
                static_cast<double>(grid.getXMin()), static_cast<double>(grid.getYMin()));
  EXPECT_NE(text.str().find(origin), std::string::npos) << text.str();
}

TEST_F(ExportAll, MrptsRosMapConverterRebuildsTheGridmapFromThePngAndYaml) {
  // MRPT's own reader of ROS maps, given map.yaml and map.png, must make the very grid of
  // map.gridmap: the image's orientation, the origin and the resolution agree.
  if (!fs::exists("/usr/bin/ros-map-yaml2mrpt"))
    GTEST_SKIP() << "ros-map-yaml2mrpt (apt mrpt-apps) missing";
  const fs::path converted = folder_->dir() / "converted";
  fs::create_directories(converted);
  const auto [out, status] =
      run("/usr/bin/ros-map-yaml2mrpt -q -w -i " + file("map.yaml") + " -d " + converted.string());
  ASSERT_EQ(status, 0) << out;
  mrpt::maps::COccupancyGridMap2D ours, theirs;
  {
    mrpt::io::CFileGZInputStream in(file("map.gridmap"));
    mrpt::serialization::archiveFrom(in) >> ours;
  }
  {
    mrpt::io::CFileGZInputStream in((converted / "map.gridmap.gz").string());
    mrpt::serialization::archiveFrom(in) >> theirs;
  }
  ASSERT_EQ(ours.getSizeX(), theirs.getSizeX());
  ASSERT_EQ(ours.getSizeY(), theirs.getSizeY());
  EXPECT_NEAR(ours.getXMin(), theirs.getXMin(), 1e-4);
  EXPECT_NEAR(ours.getYMin(), theirs.getYMin(), 1e-4);
  int differ = 0;
  for (unsigned cy = 0; cy < ours.getSizeY(); ++cy)
    for (unsigned cx = 0; cx < ours.getSizeX(); ++cx)
      differ += std::abs(ours.getCell(cx, cy) - theirs.getCell(cx, cy)) > 0.1f;
  EXPECT_EQ(differ, 0);
}

TEST(OccupancyGrid, KerbsAndSlopesStayFreeAStepAndAPoleAreObstaclesACanopyIsIgnored) {
  dlo::WeightedCloud cloud;
  auto add = [&](double x, double y, double z) {
    cloud.push_back(dlo::WeightedPoint{Eigen::Vector3f(x, y, z), 1});
  };
  // Ground rising at 20 % along x, a 0.13 m kerb along y = 2, a 0.6 m step along y = 6, a pole
  // at (10, 4) and a canopy 4 m up over (15, 4).
  for (double x = 0.0; x <= 20.0; x += 0.1) {
    for (double y = 0.0; y <= 8.0; y += 0.1) {
      double z = 0.2 * x;
      if (y >= 2.0) z += 0.13;
      if (y >= 6.0) z += 0.6;
      add(x, y, z);
    }
  }
  for (double z = 0.0; z <= 3.0; z += 0.1) add(10.05, 4.05, 0.2 * 10.0 + 0.13 + z);
  for (double x = 14.0; x <= 16.0; x += 0.1) add(x, 4.05, 0.2 * x + 0.13 + 4.0);
  dlo::OccupancyGridOptions o;
  dlo::OccupancyGridAccumulator acc(o);
  acc.extend(cloud);
  acc.ground(cloud);
  acc.classify(cloud);
  const mrpt::maps::COccupancyGridMap2D g = acc.grid();
  EXPECT_GT(g.getPos(5.05, 1.05), 0.8f) << "sloped ground";
  EXPECT_GT(g.getPos(5.05, 2.05), 0.8f) << "the kerb";
  EXPECT_GT(g.getPos(18.05, 4.05), 0.8f) << "steep ground far up the slope";
  EXPECT_LT(g.getPos(5.05, 6.05), 0.2f) << "the step";
  EXPECT_LT(g.getPos(10.05, 4.05), 0.2f) << "the pole";
  EXPECT_GT(g.getPos(15.05, 4.05), 0.8f) << "under the canopy";
  EXPECT_NEAR(g.getPos(-1.0, -1.0), 0.5f, 0.01f) << "the margin, unseen";
}

TEST_F(ExportAll, PlyMapIsInTheWorldFrameAndDecimated) {
  const dlo::PointCloud points = dlo::loadPlyFile(file("map.ply"));
  ASSERT_GT(points.size(), 1000u);
  size_t raw = 0;
  for (const auto& kf : map_->keyframes) raw += kf.cloud.size();
  EXPECT_LT(points.size(), raw);  // overlapping keyframes were merged
  size_t on_box = 0;
  for (const Eigen::Vector3f& p : points) {
    EXPECT_GE(p.z(), -1e-4);
    EXPECT_LE(p.z(), SyntheticWorld::kBoxHeight + 1e-4);
    EXPECT_LE(std::hypot(p.x() - SyntheticWorld::kBoxX, p.y() - SyntheticWorld::kBoxY),
              SyntheticWorld::kRadius + 20.5);
    if (p.z() > SyntheticWorld::kBoxHeight - 0.01) ++on_box;
  }
  EXPECT_GT(on_box, 300u);  // the 4 x 4 m box top at 0.2 m voxels: ~400
}

TEST_F(ExportAll, SceneLoadsBack) {
  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(file("map.3Dscene")));
  EXPECT_TRUE(scene.getByName("trajectory"));
  EXPECT_TRUE(scene.getByName("loop_closures"));
  // Cloud, trajectory, loops and one corner per keyframe.
  EXPECT_EQ(scene.getViewport("main")->size(), 3 + map_->keyframes.size());
}

TEST_F(ExportAll, HeightMapImageIsColourfulWithTheTrajectory) {
  const cv::Mat image = cv::imread(file("heightmap.png"), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_GE(std::max(image.cols, image.rows), 1000);
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 30.0);
  // Magenta loop-closure pixels (the 9 -> 0 edge) are present.
  cv::Mat magenta;
  cv::inRange(image, cv::Scalar(200, 0, 200), cv::Scalar(255, 60, 255), magenta);
  EXPECT_GT(cv::countNonZero(magenta), 20);
}

TEST_F(ExportAll, RenderedImageShowsTheMap) {
  const std::string warning = warningAbout("map_render.png");
  if (!warning.empty()) GTEST_SKIP() << "no off-screen rendering here: " << warning;
  const cv::Mat image = cv::imread(file("map_render.png"), cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 1280);
  EXPECT_EQ(image.rows, 960);
  cv::Scalar mean, stddev;
  cv::meanStdDev(image, mean, stddev);
  EXPECT_GT(stddev[0] + stddev[1] + stddev[2], 20.0) << "blank render";
}
