// loadPriorMap() on folders that are not a dlo-slam map: one InputError naming the file. The
// Localizer itself is tested on simulated drives in test_slam_loop.cpp.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "dlo/export/simple_map_export.h"
#include "dlo/files/error.h"
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
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dlo_prior_map_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
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

}  // namespace
}  // namespace dlo
