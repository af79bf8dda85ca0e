// combinePasses(): several runs of one method over the same scans (dlo-bench --repeat) as one.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "dlo/bench/method_run.h"

namespace dlo::bench {
namespace {

/// A run of `ms.size()` scans at 0.1 s intervals, the vehicle moving 1 m per scan along x
/// (plus `offset` metres), taking `ms` milliseconds per scan.
MethodRun pass(const std::vector<double>& ms, double peak_mb, double offset = 0.0) {
  MethodRun run;
  run.method = "m";
  run.ms = ms;
  run.peak_memory_mb = peak_mb;
  run.baseline_memory_mb = 10.0;
  for (size_t i = 0; i < ms.size(); ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation().x() = static_cast<double>(i) + offset;
    run.trajectory.push_back(0.1 * static_cast<double>(i), pose);
  }
  return run;
}

TEST(CombinePasses, EachScanTakesTheMedianOfItsTimesInThePasses) {
  // Scan 0 was slow in pass 2 only, scan 1 in passes 1 and 3: one slow pass moves nothing, a
  // majority does.
  const MethodRun r = combinePasses(
      {pass({1.0, 5.0, 2.0}, 100.0), pass({9.0, 1.0, 2.5}, 120.0), pass({1.5, 6.0, 3.0}, 110.0)});
  EXPECT_TRUE(r.error.empty());
  EXPECT_EQ(r.passes, 3);
  ASSERT_EQ(r.ms.size(), 3u);
  EXPECT_DOUBLE_EQ(r.ms[0], 1.5);
  EXPECT_DOUBLE_EQ(r.ms[1], 5.0);
  EXPECT_DOUBLE_EQ(r.ms[2], 2.5);
  EXPECT_DOUBLE_EQ(r.peak_memory_mb, 120.0);
  EXPECT_DOUBLE_EQ(r.baseline_memory_mb, 10.0);
  EXPECT_EQ(r.trajectory.size(), 3u);
  EXPECT_DOUBLE_EQ(r.pass_disagreement_m, 0.0);
}

TEST(CombinePasses, AnEvenNumberOfPassesAveragesTheTwoMiddleTimes) {
  const MethodRun r = combinePasses(
      {pass({4.0, 1.0}, 1.0), pass({1.0, 2.0}, 1.0), pass({2.0, 8.0}, 1.0), pass({3.0, 3.0}, 1.0)});
  ASSERT_EQ(r.ms.size(), 2u);
  EXPECT_DOUBLE_EQ(r.ms[0], 2.5);
  EXPECT_DOUBLE_EQ(r.ms[1], 2.5);
  EXPECT_DOUBLE_EQ(combinePasses({pass({1.0}, 1.0), pass({2.0}, 1.0)}).ms[0], 1.5);
}

TEST(CombinePasses, OnePassIsReturnedAsItIs) {
  const MethodRun one = pass({3.0, 1.0, 2.0}, 50.0);
  const MethodRun r = combinePasses({one});
  EXPECT_EQ(r.ms, one.ms);
  EXPECT_EQ(r.passes, 1);
  EXPECT_DOUBLE_EQ(r.peak_memory_mb, 50.0);
}

TEST(CombinePasses, PassesThatDisagreeSayByHowMuchAndTheFirstTrajectoryIsKept) {
  const MethodRun r =
      combinePasses({pass({1.0, 1.0}, 1.0), pass({1.0, 1.0}, 1.0, 0.25), pass({1.0, 1.0}, 1.0)});
  EXPECT_DOUBLE_EQ(r.pass_disagreement_m, 0.25);
  EXPECT_DOUBLE_EQ(r.trajectory.poses[1].translation().x(), 1.0);
}

TEST(CombinePasses, PassesOfDifferentLengthsAreCutToTheShortest) {
  const MethodRun r = combinePasses({pass({1.0, 2.0, 3.0}, 1.0), pass({3.0, 2.0}, 1.0)});
  EXPECT_EQ(r.ms.size(), 2u);
  EXPECT_EQ(r.trajectory.size(), 2u);
  EXPECT_EQ(r.trajectory.times.size(), 2u);
}

TEST(CombinePasses, AFailedPassIsTheResult) {
  MethodRun failed = pass({1.0}, 1.0);
  failed.error = "the process running it died of signal 11 (Segmentation fault).";
  const MethodRun r = combinePasses({pass({1.0, 2.0}, 1.0), failed, pass({1.0, 2.0}, 1.0)});
  EXPECT_EQ(r.error, failed.error);
  EXPECT_EQ(r.passes, 3);
  EXPECT_THROW(combinePasses({}), std::invalid_argument);
}

}  // namespace
}  // namespace dlo::bench
