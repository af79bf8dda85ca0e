// Specification of timestamp matching, ATE, RPE and the KITTI drift metric on synthetic
// trajectories with known errors.
#include <gtest/gtest.h>

#include <cmath>

#include "dlo/metrics/absolute_trajectory_error.h"
#include "dlo/metrics/kitti_drift.h"
#include "dlo/metrics/relative_pose_error.h"
#include "dlo/metrics/timestamp_matching.h"

using dlo::metrics::Alignment;
using dlo::metrics::Trajectory;

namespace {

Eigen::Isometry3d pose(double x, double y, double z, double yaw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  p.translation() = Eigen::Vector3d(x, y, z);
  return p;
}

/// A winding drive: `n` poses `step` m apart along a sine-like path (heading amplitude `wobble`
/// rad), heading along the motion.
Trajectory drive(size_t n, double step = 1.0, double wobble = 0.4) {
  Trajectory t;
  double x = 0, y = 0, yaw = 0;
  for (size_t i = 0; i < n; ++i) {
    t.push_back(0.1 * static_cast<double>(i), pose(x, y, 0.01 * x, yaw));
    yaw = wobble * std::sin(0.02 * static_cast<double>(i));
    x += step * std::cos(yaw);
    y += step * std::sin(yaw);
  }
  return t;
}

/// Every pose pre-multiplied by `offset` (a rigid error of the whole trajectory).
Trajectory transformed(const Trajectory& t, const Eigen::Isometry3d& offset) {
  Trajectory out = t;
  for (auto& p : out.poses) p = offset * p;
  return out;
}

}  // namespace

TEST(TimestampMatching, PairsNearestWithinToleranceOnce) {
  Trajectory est, ref;
  for (double t : {0.00, 0.11, 0.19, 0.50, 0.90}) est.push_back(t, pose(t, 0, 0, 0));
  for (double t : {0.0, 0.1, 0.2, 0.3, 1.0}) ref.push_back(t, pose(t, 0, 0, 0));
  const auto pairs = dlo::metrics::matchTimestamps(est, ref, 0.02);
  ASSERT_EQ(pairs.size(), 3u);  // 0.50 and 0.90 have no reference within 20 ms
  EXPECT_EQ(pairs[0], std::make_pair(size_t{0}, size_t{0}));
  EXPECT_EQ(pairs[1], std::make_pair(size_t{1}, size_t{1}));
  EXPECT_EQ(pairs[2], std::make_pair(size_t{2}, size_t{2}));
}

TEST(TimestampMatching, AReferencePoseIsUsedByTheClosestEstimateOnly) {
  Trajectory est, ref;
  est.push_back(0.98, pose(0, 0, 0, 0));
  est.push_back(1.01, pose(0, 0, 0, 0));
  ref.push_back(1.0, pose(0, 0, 0, 0));
  const auto pairs = dlo::metrics::matchTimestamps(est, ref, 0.05);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].first, 1u);
}

TEST(AbsoluteTrajectoryError, IdenticalTrajectoriesGiveZero) {
  const Trajectory t = drive(200);
  for (Alignment a : {Alignment::kFirstPose, Alignment::kUmeyama}) {
    const auto r = dlo::metrics::absoluteTrajectoryError(t, t, a);
    EXPECT_EQ(r.alignment, a);
    EXPECT_NEAR(r.error.rmse, 0.0, 1e-9);
    EXPECT_NEAR(r.error.max, 0.0, 1e-9);
    EXPECT_EQ(r.error.count, 200u);
  }
}

TEST(AbsoluteTrajectoryError, RigidOffsetOfTheWholeTrajectoryIsRemovedByAlignment) {
  const Trajectory ref = drive(200);
  // The estimate is the reference seen from a frame rotated by 10 deg and shifted: a rigid
  // error of the whole trajectory, which either alignment removes completely.
  const Trajectory est = transformed(ref, pose(3.0, -4.0, 0.0, 10 * M_PI / 180));
  const auto umeyama = dlo::metrics::absoluteTrajectoryError(est, ref, Alignment::kUmeyama);
  EXPECT_EQ(umeyama.alignment, Alignment::kUmeyama);
  EXPECT_NEAR(umeyama.error.rmse, 0.0, 1e-6);
  const auto first = dlo::metrics::absoluteTrajectoryError(est, ref, Alignment::kFirstPose);
  EXPECT_NEAR(first.error.rmse, 0.0, 1e-6);
}

TEST(AbsoluteTrajectoryError, ConstantOffsetAfterTheFirstPoseIsTheFirstPoseError) {
  // The first pose agrees, every later position is 0.5 m off (0.3, 0.4, 0): first-pose
  // alignment sees exactly the offset; Umeyama explains almost all of it by a shift.
  const Trajectory ref = drive(200);
  Trajectory est = ref;
  for (size_t i = 1; i < est.size(); ++i)
    est.poses[i].translation() += Eigen::Vector3d(0.3, 0.4, 0);
  const auto f = dlo::metrics::absoluteTrajectoryError(est, ref, Alignment::kFirstPose);
  EXPECT_NEAR(f.error.median, 0.5, 1e-9);
  EXPECT_NEAR(f.error.max, 0.5, 1e-9);
  EXPECT_NEAR(f.error.mean, 0.5 * 199 / 200, 1e-9);
  const auto u = dlo::metrics::absoluteTrajectoryError(est, ref, Alignment::kUmeyama);
  EXPECT_LT(u.error.median, 0.01);
  EXPECT_LT(u.error.rmse, 0.05);
}

TEST(AbsoluteTrajectoryError, KnownHeadingErrorAtTheStartGrowsLinearly) {
  // A straight 100 m drive whose estimate starts with a 1 deg heading error: after first-pose
  // alignment the position error at distance d is 2 d sin(0.5 deg).
  Trajectory ref, est;
  const double err = 1.0 * M_PI / 180;
  for (int i = 0; i <= 100; ++i) {
    ref.push_back(i, pose(i, 0, 0, 0));
    est.push_back(i, pose(i * std::cos(err), i * std::sin(err), 0, err));
  }
  est.poses[0] = ref.poses[0];
  const auto r = dlo::metrics::absoluteTrajectoryError(est, ref, Alignment::kFirstPose);
  EXPECT_NEAR(r.error.max, 2 * 100 * std::sin(err / 2), 1e-9);
}

TEST(AbsoluteTrajectoryError, UmeyamaOnCollinearPositionsFallsBackToFirstPose) {
  Trajectory t;
  for (int i = 0; i < 10; ++i) t.push_back(i, pose(i, 0, 0, 0));
  const auto r = dlo::metrics::absoluteTrajectoryError(t, t, Alignment::kUmeyama);
  EXPECT_EQ(r.alignment, Alignment::kFirstPose);
  EXPECT_EQ(dlo::metrics::alignmentName(r.alignment), "first-pose");
}

TEST(AbsoluteTrajectoryError, MismatchedSizesAreRejected) {
  EXPECT_THROW(dlo::metrics::absoluteTrajectoryError(drive(5), drive(6), Alignment::kUmeyama),
               std::invalid_argument);
}

TEST(RelativePoseError, ConstantYawRateErrorIsSeenPerStep) {
  // The estimate turns 0.1 deg more than the reference at every step.
  Trajectory ref, est;
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity(), e = r;
  const Eigen::Isometry3d step = pose(1, 0, 0, 0.02);
  const Eigen::Isometry3d bad = pose(1, 0, 0, 0.02 + 0.1 * M_PI / 180);
  for (int i = 0; i < 50; ++i) {
    ref.push_back(i, r);
    est.push_back(i, e);
    r = r * step;
    e = e * bad;
  }
  const auto rpe = dlo::metrics::relativePoseError(est, ref, 1);
  EXPECT_NEAR(rpe.rotation.mean, 0.1, 1e-9);
  EXPECT_NEAR(rpe.rotation.max, 0.1, 1e-9);
  EXPECT_NEAR(rpe.translation.max, 0.0, 1e-9);
  const auto rpe5 = dlo::metrics::relativePoseError(est, ref, 5);
  EXPECT_NEAR(rpe5.rotation.median, 0.5, 1e-9);
  EXPECT_GT(rpe5.translation.median, 0.0);
}

TEST(KittiDrift, IdenticalTrajectoriesHaveNoDrift) {
  const Trajectory t = drive(1000);
  const auto r = dlo::metrics::kittiDrift(t, t);
  EXPECT_FALSE(r.short_sequence);
  EXPECT_EQ(r.per_length.size(), 8u);
  EXPECT_NEAR(r.translation_percent, 0.0, 1e-9);
  EXPECT_NEAR(r.rotation_deg_per_100m, 0.0, 1e-9);
}

TEST(KittiDrift, ScaleErrorOfOnePercentIsOnePercentDrift) {
  // A nearly straight drive: on a winding one the chord of a long segment is shorter than its
  // path length and the ratio drops below 1 % (as it does in the devkit).
  const Trajectory ref = drive(1000, 1.0, 0.05);
  Trajectory est = ref;
  for (auto& p : est.poses) p.translation() *= 1.01;
  const auto r = dlo::metrics::kittiDrift(est, ref);
  // Segments end at the first frame beyond the length (up to 1 m further) and chords are a bit
  // shorter than arcs, so the ratio is within a few hundredths of a percent of 1 %.
  EXPECT_NEAR(r.translation_percent, 1.0, 0.02);
  EXPECT_NEAR(r.rotation_deg_per_100m, 0.0, 1e-9);
  // 1000 m of poses: lengths up to 800 m fit; segments start every 10 frames.
  ASSERT_EQ(r.per_length.size(), 8u);
  EXPECT_EQ(r.per_length.front().length, 100.0);
  EXPECT_EQ(r.per_length.back().length, 800.0);
  EXPECT_GT(r.per_length.front().segments, r.per_length.back().segments);
}

TEST(KittiDrift, ConstantYawRateErrorGivesRotationalDrift) {
  // 0.01 deg too much turn per metre: 1 deg per 100 m.
  Trajectory ref, est;
  Eigen::Isometry3d r = Eigen::Isometry3d::Identity(), e = r;
  for (int i = 0; i < 400; ++i) {
    ref.push_back(i, r);
    est.push_back(i, e);
    r = r * pose(1, 0, 0, 0.001);
    e = e * pose(1, 0, 0, 0.001 + 0.01 * M_PI / 180);
  }
  const auto d = dlo::metrics::kittiDrift(est, ref);
  EXPECT_EQ(d.per_length.size(), 3u);  // 100, 200 and 300 m fit in 399 m
  // A segment spans a little more than its length (first frame beyond it).
  EXPECT_NEAR(d.rotation_deg_per_100m, 1.0, 0.01);
}

TEST(KittiDrift, ShortSequenceUsesFractionsOfItsLength) {
  const Trajectory ref = drive(41, 0.5);  // 20 m
  Trajectory est = ref;
  for (auto& p : est.poses) p.translation() *= 1.01;
  dlo::metrics::KittiDriftParams params;
  params.step = 1;
  const auto r = dlo::metrics::kittiDrift(est, ref, params);
  EXPECT_TRUE(r.short_sequence);
  ASSERT_EQ(r.per_length.size(), 8u);
  // 10 % and 80 % of the ~20 m path.
  EXPECT_NEAR(r.per_length.front().length, 2.0, 0.01);
  EXPECT_NEAR(r.per_length.back().length, 16.0, 0.01);
  EXPECT_NEAR(r.translation_percent, 1.0, 0.05);
}
