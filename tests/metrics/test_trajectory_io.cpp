// Specification of the TUM and KITTI trajectory readers and writers.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dlo/metrics/trajectory_io.h"

namespace fs = std::filesystem;
using dlo::metrics::Trajectory;

namespace {

/// A fresh empty folder per test, removed at the end.
class TrajectoryFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("dlo_metrics_io_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void writeText(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
  }
  fs::path dir_;
};

Trajectory helix(size_t n) {
  Trajectory t;
  for (size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i);
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = (Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05 * a, Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    p.translation() = Eigen::Vector3d(10 * std::cos(a), 10 * std::sin(a), 0.2 * a);
    t.push_back(1.5e9 + 0.1 * static_cast<double>(i), p);
  }
  return t;
}

void expectSamePoses(const Trajectory& a, const Trajectory& b, double tol) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_TRUE(a.poses[i].isApprox(b.poses[i], tol)) << "pose " << i;
  }
}

}  // namespace

TEST_F(TrajectoryFiles, TumRoundTripKeepsTimesAndPoses) {
  const Trajectory t = helix(50);
  dlo::metrics::writeTumTrajectory(path("a.tum"), t);
  EXPECT_FALSE(fs::exists(path("a.tum.tmp")));
  const Trajectory back = dlo::metrics::readTumTrajectory(path("a.tum"));
  expectSamePoses(t, back, 1e-8);
  for (size_t i = 0; i < t.size(); ++i) EXPECT_NEAR(t.times[i], back.times[i], 1e-6);
  EXPECT_EQ(dlo::metrics::detectTrajectoryFormat(path("a.tum")),
            dlo::metrics::TrajectoryFormat::kTum);
}

TEST_F(TrajectoryFiles, TheStreamingWriterStampsExactlyAndWritesTheSameLinesAsTheWholeFile) {
  const Trajectory t = helix(3);
  {
    dlo::metrics::TumWriter out(path("s.tum"), "# a header\n");
    // Seconds and nanoseconds as a simulator's clock has them: no rounding through a double.
    out.write(1704067200, 1, t.poses[0]);
    out.write(1704067200, 999999999, t.poses[1]);
    out.write(t.times[2], t.poses[2]);
    EXPECT_FALSE(fs::exists(path("s.tum"))) << "visible before commit()";
    out.commit();
  }
  std::ifstream in(path("s.tum"));
  std::string header, first, second, third;
  std::getline(in, header);
  std::getline(in, first);
  std::getline(in, second);
  std::getline(in, third);
  EXPECT_EQ(header, "# a header");
  EXPECT_EQ(first.substr(0, 21), "1704067200.000000001 ");
  EXPECT_EQ(second.substr(0, 21), "1704067200.999999999 ");
  // The whole-file writer's line for the same pose and time.
  Trajectory one;
  one.push_back(t.times[2], t.poses[2]);
  dlo::metrics::writeTumTrajectory(path("w.tum"), one, dlo::metrics::TumHeader::kNone);
  std::ifstream whole(path("w.tum"));
  std::string line;
  std::getline(whole, line);
  EXPECT_EQ(third, line);
}

TEST_F(TrajectoryFiles, AStreamingWriterDroppedBeforeCommitLeavesThePreviousFile) {
  writeText("keep.tum", "previous\n");
  {
    dlo::metrics::TumWriter out(path("keep.tum"), "");
    out.write(1.0, Eigen::Isometry3d::Identity());
  }  // an error part way: no commit()
  std::ifstream in(path("keep.tum"));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "previous");
  EXPECT_FALSE(fs::exists(path("keep.tum.tmp")));
}

TEST_F(TrajectoryFiles, KittiRoundTripWithSeparateTimestamps) {
  const Trajectory t = helix(50);
  dlo::metrics::writeKittiTrajectory(path("poses.txt"), t);
  dlo::metrics::writeTimestamps(path("times.txt"), t.times);
  EXPECT_EQ(dlo::metrics::detectTrajectoryFormat(path("poses.txt")),
            dlo::metrics::TrajectoryFormat::kKitti);
  const Trajectory back = dlo::metrics::readTrajectory(
      path("poses.txt"), dlo::metrics::readTimestamps(path("times.txt")));
  expectSamePoses(t, back, 1e-8);
  EXPECT_NEAR(back.times.back(), t.times.back(), 1e-6);
}

TEST_F(TrajectoryFiles, KittiWithoutTimestampsIsStampedByIndex) {
  writeText("p.txt", "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 4 0 1 0 5 0 0 1 6\n");
  const Trajectory t = dlo::metrics::readKittiTrajectory(path("p.txt"));
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t.times[1], 1.0);
  EXPECT_TRUE(t.poses[1].translation().isApprox(Eigen::Vector3d(4, 5, 6)));
}

TEST_F(TrajectoryFiles, TumCommentsAndBlankLinesAreSkipped) {
  writeText("c.tum", "# header\n\n1.0 1 2 3 0 0 0 1\n  # indented comment\n2.0 4 5 6 0 0 0 2\n");
  const Trajectory t = dlo::metrics::readTumTrajectory(path("c.tum"));
  ASSERT_EQ(t.size(), 2u);
  // The quaternion (0 0 0 2) is normalised to the identity.
  EXPECT_TRUE(t.poses[1].rotation().isApprox(Eigen::Matrix3d::Identity()));
}

TEST_F(TrajectoryFiles, MalformedTumLineNamesFileAndLine) {
  writeText("bad.tum", "# c\n1.0 1 2 3 0 0 0 1\n2.0 4 five 6 0 0 0 1\n");
  try {
    dlo::metrics::readTumTrajectory(path("bad.tum"));
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.tum"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
}

TEST_F(TrajectoryFiles, WrongColumnCountNamesTheLine) {
  writeText("short.txt", "1 0 0 1 0 1 0 2 0 0 1 3\n1 0 0 1 0 1 0 2 0 0 1\n");
  try {
    dlo::metrics::readKittiTrajectory(path("short.txt"));
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("got 11"), std::string::npos) << e.what();
  }
}

TEST_F(TrajectoryFiles, TimestampCountMustMatchPoseCount) {
  writeText("p.txt", "1 0 0 1 0 1 0 2 0 0 1 3\n");
  EXPECT_THROW(dlo::metrics::readKittiTrajectory(path("p.txt"), {0.0, 0.1}), std::runtime_error);
}

TEST_F(TrajectoryFiles, UnknownFormatIsRejected) {
  writeText("x.txt", "1 2 3\n");
  EXPECT_THROW(dlo::metrics::detectTrajectoryFormat(path("x.txt")), std::runtime_error);
  EXPECT_THROW(dlo::metrics::readTrajectory(path("missing.txt")), std::runtime_error);
}

TEST_F(TrajectoryFiles, WritingIntoMissingFolderThrowsAndLeavesNothing) {
  const std::string p = path("no/such/dir/a.tum");
  EXPECT_THROW(dlo::metrics::writeTumTrajectory(p, helix(3)), std::runtime_error);
  EXPECT_FALSE(fs::exists(p));
  EXPECT_FALSE(fs::exists(p + ".tmp"));
}
