// heightmap_centroids.bin: written and read back, and every kind of bad file refused with one
// InputError naming it.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "../temp_dir.h"
#include "dlo/files/error.h"
#include "dlo/formats/height_map_centroids.h"

namespace dlo {
namespace {

namespace fs = std::filesystem;

class CentroidFile : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return tmp_.path(name); }
  /// The message of the InputError that reading `file` throws, or "" if it throws none.
  static std::string readError(const std::string& file) {
    try {
      readHeightMapCentroids(file);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  /// Writes `bytes` gzip-compressed, as the format is.
  static void writeGz(const std::string& file, const std::string& bytes) {
    gzFile out = gzopen(file.c_str(), "wb");
    ASSERT_NE(out, nullptr);
    if (!bytes.empty()) gzwrite(out, bytes.data(), static_cast<unsigned>(bytes.size()));
    gzclose(out);
  }
  test::TempDir tmp_;
};

/// A 3 x 2 grid whose places count up from 0 in steps of 40.
HeightMapCentroids sample() {
  HeightMapCentroids c;
  c.cols = 3;
  c.rows = 2;
  for (int i = 0; i < 12; ++i) c.places.push_back(static_cast<std::uint8_t>(40 * i % 256));
  return c;
}

TEST(HeightMapCentroids, QuantisedPlacesAreWithinHalfAStepOfTheFraction) {
  for (double f : {0.0, 0.001, 0.25, 0.5, 0.73, 0.999}) {
    EXPECT_NEAR(HeightMapCentroids::fraction(HeightMapCentroids::quantise(f)), f, 0.5 / 256 + 1e-7)
        << f;
  }
  EXPECT_EQ(HeightMapCentroids::quantise(1.0), 255);  // the cell's far edge stays in the cell
  EXPECT_EQ(HeightMapCentroids::quantise(-0.2), 0);
  EXPECT_EQ(HeightMapCentroids::quantise(std::nan("")), 0);
}

TEST_F(CentroidFile, ReadsBackWhatWasWritten) {
  const HeightMapCentroids c = sample();
  writeHeightMapCentroids(c, path("c.bin"));
  EXPECT_FALSE(fs::exists(path("c.bin.tmp")));
  const HeightMapCentroids back = readHeightMapCentroids(path("c.bin"));
  EXPECT_EQ(back.cols, 3u);
  EXPECT_EQ(back.rows, 2u);
  EXPECT_EQ(back.places, c.places);
}

TEST_F(CentroidFile, PlacesThatDoNotMatchTheCellsAreNotWritten) {
  HeightMapCentroids c = sample();
  c.places.pop_back();
  EXPECT_THROW(writeHeightMapCentroids(c, path("c.bin")), OutputError);
  EXPECT_FALSE(fs::exists(path("c.bin")));
}

TEST_F(CentroidFile, BadFilesAreNamed) {
  std::string message = readError(path("missing.bin"));
  EXPECT_NE(message.find("missing.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("does not exist"), std::string::npos) << message;

  std::ofstream(path("text.bin")) << "not a centroid file at all";
  message = readError(path("text.bin"));
  EXPECT_NE(message.find("text.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("DLOHMC01"), std::string::npos) << message;

  writeGz(path("empty.bin"), "");
  message = readError(path("empty.bin"));
  EXPECT_NE(message.find("DLOHMC01"), std::string::npos) << message;

  // A header of 0 x 5 cells.
  writeGz(path("zero.bin"), std::string("DLOHMC01") + std::string("\0\0\0\0\5\0\0\0", 8));
  message = readError(path("zero.bin"));
  EXPECT_NE(message.find("0 x 5"), std::string::npos) << message;

  // The sample's file cut short, and with a byte too many.
  writeHeightMapCentroids(sample(), path("whole.bin"));
  gzFile in = gzopen(path("whole.bin").c_str(), "rb");
  ASSERT_NE(in, nullptr);
  std::string bytes(64, '\0');
  bytes.resize(static_cast<size_t>(gzread(in, bytes.data(), 64)));
  gzclose(in);
  ASSERT_EQ(bytes.size(), 16u + 12u);
  writeGz(path("short.bin"), bytes.substr(0, bytes.size() - 1));
  message = readError(path("short.bin"));
  EXPECT_NE(message.find("short.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  writeGz(path("long.bin"), bytes + "x");
  message = readError(path("long.bin"));
  EXPECT_NE(message.find("long.bin"), std::string::npos) << message;
  EXPECT_NE(message.find("more than"), std::string::npos) << message;
}

}  // namespace
}  // namespace dlo
