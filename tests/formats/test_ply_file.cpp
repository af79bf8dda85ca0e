// dlo::loadPlyFile: the PLY encodings, and malformed files as errors rather than crashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>

#include "dlo/files/error.h"
#include "dlo/formats/ply_file.h"

namespace dlo {
namespace {

class PlyFile : public ::testing::Test {
 protected:
  std::string write(const std::string& bytes) {
    std::ofstream(path_, std::ios::binary) << bytes;
    return path_;
  }
  /// The message of the InputError loadPlyFile throws, or "" if none.
  std::string errorOf(const std::string& bytes) {
    try {
      loadPlyFile(write(bytes));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  void TearDown() override { std::remove(path_.c_str()); }
  // One file per test: ctest runs the tests of this binary in parallel processes.
  const std::string path_ = testing::TempDir() + "dlo_ply_test_" +
                            testing::UnitTest::GetInstance()->current_test_info()->name() + ".ply";
};

/// `v` as the bytes of a float in the given byte order.
std::string floatBytes(float v, bool big_endian) {
  char b[4];
  std::memcpy(b, &v, 4);
  std::string s(b, 4);
  const std::uint16_t one = 1;
  const bool host_little = *reinterpret_cast<const std::uint8_t*>(&one) == 1;
  if (big_endian == host_little) std::reverse(s.begin(), s.end());
  return s;
}

TEST_F(PlyFile, ReadsAsciiVerticesSkippingOtherElementsAndProperties) {
  const auto points = loadPlyFile(
      write("ply\nformat ascii 1.0\ncomment made by hand\nelement face 1\n"
            "property list uchar int vertex_indices\nelement vertex 2\nproperty double intensity\n"
            "property float x\nproperty float y\nproperty float z\nproperty uchar red\nend_header\n"
            "3 0 1 1\n0.5 1 2 3 255\n0.25 -4 5.5 nan 0\n"));
  ASSERT_EQ(points.size(), 1u);  // the NaN vertex is dropped
  EXPECT_EQ(points[0], Eigen::Vector3f(1, 2, 3));
}

TEST_F(PlyFile, ReadsBinaryLittleAndBigEndian) {
  for (bool big : {false, true}) {
    std::string bytes = std::string("ply\nformat ") +
                        (big ? "binary_big_endian" : "binary_little_endian") +
                        " 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                        "property float z\nproperty uchar tag\nend_header\n";
    for (float v : {1.5f, -2.0f, 3.25f}) bytes += floatBytes(v, big);
    bytes += '\x07';
    for (float v : {4.0f, 5.0f, -6.5f}) bytes += floatBytes(v, big);
    bytes += '\x08';
    const auto points = loadPlyFile(write(bytes));
    ASSERT_EQ(points.size(), 2u) << big;
    EXPECT_EQ(points[0], Eigen::Vector3f(1.5f, -2.0f, 3.25f)) << big;
    EXPECT_EQ(points[1], Eigen::Vector3f(4.0f, 5.0f, -6.5f)) << big;
  }
}

TEST_F(PlyFile, MalformedFilesThrowNamingTheFile) {
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n";
  for (const std::string& bytes :
       {std::string(""), std::string("garbage\n"), std::string("ply\n"),
        header + "1 2 3\n4 5\n",  // truncated body
        std::string("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n"),
        std::string("ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
                    "property float y\nproperty float z\nend_header\nab")}) {
    const std::string msg = errorOf(bytes);
    EXPECT_NE(msg.find(path_), std::string::npos) << "for: " << bytes << " -> " << msg;
  }
  EXPECT_NE(errorOf(header + "1 2 3\n4 5\n").find("after 1 of its 5 vertex"), std::string::npos);
}

TEST_F(PlyFile, MissingFileThrowsNamingIt) {
  EXPECT_THROW(loadPlyFile("/nonexistent/scan.ply"), InputError);
}

}  // namespace
}  // namespace dlo
