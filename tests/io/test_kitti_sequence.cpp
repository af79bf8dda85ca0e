// KITTI sequence folders: files, times, poses, the camera-to-LiDAR conversion, malformed input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/formats/kitti_sequence.h"
#include "dlo/mrpt/kitti_conversion.h"
#include "io_test_helpers.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

/// Expects `f` to throw an InputError whose message contains every one of `parts`.
template <class F>
void expectInputError(F f, const std::vector<std::string>& parts) {
  try {
    f();
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

/// A sequence folder with `n` tiny scans (contents do not matter for these tests).
void makeSequence(const test::TempDir& dir, int n) {
  fs::create_directories(dir.path("seq/velodyne"));
  for (int i = n - 1; i >= 0; --i) {  // created out of order: the reader must sort
    std::ofstream f(dir.path("seq/velodyne/00000" + std::to_string(i) + ".bin"), std::ios::binary);
    const float v[4] = {1.0f, 2.0f, 3.0f, 0.5f};
    f.write(reinterpret_cast<const char*>(v), sizeof(v));
  }
}

TEST(KittiSequence, ListsScansInOrderAndAssumes10HzWithoutTimes) {
  test::TempDir dir;
  makeSequence(dir, 3);
  const KittiSequence seq = readKittiSequence(dir.path("seq"));
  ASSERT_EQ(seq.scan_files.size(), 3u);
  EXPECT_NE(seq.scan_files[0].find("000000.bin"), std::string::npos);
  EXPECT_NE(seq.scan_files[2].find("000002.bin"), std::string::npos);
  EXPECT_FALSE(seq.times_from_file);
  EXPECT_DOUBLE_EQ(seq.times[2], 0.2);
  EXPECT_TRUE(seq.lidar_poses.empty());
}

TEST(KittiSequence, ConvertsCameraPosesToTheLidarFrameWithCalib) {
  test::TempDir dir;
  makeSequence(dir, 2);
  // KITTI's Tr (velo -> cam): x_cam = -y_velo, y_cam = -z_velo, z_cam = x_velo, plus an offset.
  std::ofstream(dir.path("seq/calib.txt")) << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n"
                                              "Tr: 0 -1 0 0.1 0 0 -1 0.2 1 0 0 0.3\n";
  // The camera moves 2 m along its z axis (forward), i.e. the LiDAR moves 2 m along its x.
  std::ofstream(dir.path("seq/poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0\n"
                                              "1 0 0 0 0 1 0 0 0 0 1 2\n";
  const KittiSequence seq = readKittiSequence(dir.path("seq"));
  ASSERT_EQ(seq.lidar_poses.size(), 2u);
  EXPECT_TRUE(seq.poses_from_camera_frame);
  EXPECT_TRUE(seq.lidar_poses[0].isApprox(Eigen::Isometry3d::Identity(), 1e-12));
  const Eigen::Vector3d t = seq.lidar_poses[1].translation();
  EXPECT_NEAR(t.x(), 2.0, 1e-12);
  EXPECT_NEAR(t.y(), 0.0, 1e-12);
  EXPECT_NEAR(t.z(), 0.0, 1e-12);
  EXPECT_TRUE(seq.lidar_poses[1].linear().isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(KittiSequence, NamesFileAndLineOfMalformedInput) {
  test::TempDir dir;
  makeSequence(dir, 2);
  std::ofstream(dir.path("seq/times.txt")) << "0.0\n0.1 oops\n";
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"times.txt", "line 2"});
  std::ofstream(dir.path("seq/times.txt")) << "0.0\n0.1\n";
  std::ofstream(dir.path("seq/poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0\n";
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"poses.txt", "line 2"});
  std::ofstream(dir.path("seq/poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0\n";
  expectInputError([&] { readKittiSequence(dir.path("seq")); },
                   {"poses.txt", "1 lines", "2 scans"});
  std::ofstream(dir.path("seq/poses.txt")) << "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 1 0\n";
  std::ofstream(dir.path("seq/calib.txt")) << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\nTr 1 2\n";
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"calib.txt", "line 2"});
  std::ofstream(dir.path("seq/calib.txt")) << "P0: 1 0 0 0 0 1 0 0 0 0 1 0\n";
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"calib.txt", "Tr"});
}

TEST(KittiSequence, RejectsMissingFolders) {
  test::TempDir dir;
  expectInputError([&] { readKittiSequence(dir.path("nope")); }, {"nope"});
  fs::create_directories(dir.path("seq"));
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"velodyne/"});
  fs::create_directories(dir.path("seq/velodyne"));
  expectInputError([&] { readKittiSequence(dir.path("seq")); }, {"no .bin"});
}

TEST(KittiBin, LoadsTheRealScanWithReflectanceAndRejectsBadSizes) {
  mrpt::maps::CPointsMapXYZI map;
  EXPECT_EQ(loadKittiBinXYZI(test::sharedData("kitti_00_000000.bin.gz"), map), 0u);
  EXPECT_EQ(map.size(), 124668u);
  float max_i = 0;
  for (size_t i = 0; i < map.size(); ++i) max_i = std::max(max_i, map.getPointIntensity(i));
  EXPECT_GT(max_i, 0.0f);

  test::TempDir dir;
  std::ofstream(dir.path("bad.bin"), std::ios::binary) << std::string(20, '\0');
  expectInputError([&] { loadKittiBinXYZI(dir.path("bad.bin"), map); }, {"bad.bin", "16"});
}

}  // namespace
}  // namespace dlo
