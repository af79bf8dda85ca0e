// Recovery of known motions on the real HDL-64 scan of ../shared/data.
#include <gtest/gtest.h>

#include <cmath>

#include "../test_data.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/mrpt/scan_file.h"

namespace dlo {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Motion {
  double x, y, z, yaw_deg, pitch_deg, roll_deg;
};

class RealScanRegistration : public ::testing::TestWithParam<Motion> {
 protected:
  static void SetUpTestSuite() {
    const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
    test::splitEvenOdd(scan, *even_, *odd_);
  }
  static PointCloud* even_;
  static PointCloud* odd_;

  void recover(int dof) {
    const Motion m = GetParam();
    DloParams params;
    params.solver.dof = dof;
    const double z = dof == 6 ? m.z : 0.0;
    const double pitch = dof == 6 ? m.pitch_deg * kDeg : 0.0;
    const double roll = dof == 6 ? m.roll_deg * kDeg : 0.0;
    const Eigen::Isometry3d truth = poseFromXYZYPR(m.x, m.y, z, m.yaw_deg * kDeg, pitch, roll);
    const HeightFrame ref =
        HeightFrame::fromPoints(*even_, params.grid, params.selection, params.includeGround());
    const HeightFrame cur = HeightFrame::fromPoints(test::expressIn(*odd_, truth), params.grid,
                                                    params.selection, params.includeGround());
    const AlignmentResult r =
        DirectAligner(params.solver).align(ref, cur, Eigen::Isometry3d::Identity());
    const Eigen::Isometry3d err = truth.inverse() * r.pose;
    const double dt = err.translation().norm();
    const double dr = Eigen::AngleAxisd(err.linear()).angle() / kDeg;
    std::printf("dof %d motion (%.2f %.2f %.2f | %.1f %.1f %.1f): err %.4f m %.4f deg, it %d, "
                "cells %d, rms %.4f, solve %.2f ms\n",
                dof, m.x, m.y, z, m.yaw_deg, pitch / kDeg, roll / kDeg, dt, dr, r.iterations,
                r.cells, r.rms_height_error, r.times.solve_ms);
    EXPECT_LT(dt, 0.03);
    EXPECT_LT(dr, 0.1);
    EXPECT_FALSE(r.degenerate);
  }
};
PointCloud* RealScanRegistration::even_ = new PointCloud;
PointCloud* RealScanRegistration::odd_ = new PointCloud;

TEST_P(RealScanRegistration, RecoversKnownMotionIn3Dof) { recover(3); }
TEST_P(RealScanRegistration, RecoversKnownMotionIn6Dof) { recover(6); }

INSTANTIATE_TEST_SUITE_P(UpTo2mAnd10deg, RealScanRegistration,
                         ::testing::Values(Motion{0.0, 0.0, 0.0, 0.0, 0.0, 0.0},
                                           Motion{0.5, -0.3, 0.05, 2.0, 0.5, -0.5},
                                           Motion{1.2, 0.8, -0.10, -5.0, 1.0, 1.5},
                                           Motion{2.0, 0.0, 0.10, 10.0, -1.5, 1.0},
                                           Motion{-1.4, 1.4, 0.20, -10.0, 2.0, -2.0}));

}  // namespace
}  // namespace dlo
