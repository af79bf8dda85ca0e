// mrpt::slam::CDirectHeightAligner used where MRPT code uses CICP, on the real HDL-64 scan.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/slam/CICP.h>
#include <cmath>
#include <sstream>

#include "../test_data.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/units.h"
#include "dlo/files/error.h"
#include "dlo/formats/kitti_bin.h"
#include "dlo/mrpt/CDirectHeightAligner.h"
#include "dlo/mrpt/class_registration.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/mrpt/height_grid_map_conversion.h"
#include "dlo/mrpt/pose_conversion.h"

namespace dlo {
namespace {

using mrpt::slam::CDirectHeightAligner;

/// MRPT code that only knows the interface: this is where CICP would be used.
mrpt::poses::CPose3DPDF::Ptr registerMaps(mrpt::slam::CMetricMapsAlignmentAlgorithm& algorithm,
                                          const mrpt::maps::CMetricMap& reference,
                                          const mrpt::maps::CMetricMap& current,
                                          mrpt::slam::TMetricMapAlignmentResult& info) {
  mrpt::poses::CPose3DPDFGaussian guess;
  guess.mean = mrpt::poses::CPose3D();
  guess.cov.setDiagonal(1.0);
  return algorithm.Align3DPDF(&reference, &current, guess, info);
}

mrpt::maps::CSimplePointsMap toPointsMap(const PointCloud& cloud) {
  mrpt::maps::CSimplePointsMap map;
  map.reserve(cloud.size());
  for (const auto& p : cloud) map.insertPointFast(p.x(), p.y(), p.z());
  return map;
}

/// A 40 m x 40 m height map of 0.1 m cells centred on the sensor, as MRPT builds it.
mrpt::maps::CHeightGridMap2D toHeightMap(const PointCloud& cloud) {
  mrpt::maps::CHeightGridMap2D map(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, -20, 20, -20, 20,
                                   0.1);
  for (const auto& p : cloud) {
    if (std::abs(p.x()) < 20 && std::abs(p.y()) < 20)
      map.insertIndividualPoint(p.x(), p.y(), p.z());
  }
  return map;
}

/// Translation (m) and rotation (deg) between two poses.
std::pair<double, double> poseError(const mrpt::poses::CPose3D& estimate,
                                    const Eigen::Isometry3d& truth) {
  const Eigen::Isometry3d err = truth.inverse() * toIsometry(estimate);
  return {err.translation().norm(), Eigen::AngleAxisd(err.linear()).angle() / kDeg};
}

/// Even points as reference, odd points seen from a frame moved by `truth`.
class RealScanAligner : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const PointCloud scan = loadKittiBin(test::sharedData("kitti_00_000000.bin.gz"));
    test::splitEvenOdd(scan, even(), odd());
  }
  static PointCloud& even() {
    static PointCloud c;
    return c;
  }
  static PointCloud& odd() {
    static PointCloud c;
    return c;
  }
  const Eigen::Isometry3d truth_ = poseFromXYZYPR(1.0, -0.5, 0.0, 5.0 * kDeg, 0.0, 0.0);
};

// First in this file on purpose: nothing has called registerMrptClasses() yet, so this sees the
// registration done when the library was loaded.
TEST(CDirectHeightAlignerRtti, IsRegisteredAtLoadTime) {
  EXPECT_TRUE(mrpt::rtti::classFactory("mrpt::slam::CDirectHeightAligner"));
}

TEST(CDirectHeightAlignerRtti, IsCreatedByMrptClassFactoryByName) {
  registerMrptClasses();
  registerMrptClasses();  // idempotent
  const mrpt::rtti::CObject::Ptr obj = mrpt::rtti::classFactory("mrpt::slam::CDirectHeightAligner");
  ASSERT_TRUE(obj);
  EXPECT_STREQ(obj->GetRuntimeClass()->className, "mrpt::slam::CDirectHeightAligner");
  EXPECT_TRUE(std::dynamic_pointer_cast<mrpt::slam::CMetricMapsAlignmentAlgorithm>(obj));
  EXPECT_TRUE(mrpt::rtti::findRegisteredClass("mrpt::slam::CDirectHeightAligner"));
}

TEST(CDirectHeightAlignerRtti, CloneKeepsTheOptions) {
  CDirectHeightAligner a;
  a.options.params.grid.cols = 123;
  std::unique_ptr<mrpt::rtti::CObject> copy(a.clone());
  auto* b = dynamic_cast<CDirectHeightAligner*>(copy.get());
  ASSERT_NE(b, nullptr);
  EXPECT_EQ(b->options.params.grid.cols, 123);
}

TEST_F(RealScanAligner, ReplacesCicpBehindTheAlignmentInterface) {
  const auto ref = toPointsMap(even());
  const auto cur = toPointsMap(test::expressIn(odd(), truth_));

  mrpt::slam::CICP icp;
  mrpt::slam::CICP::TReturnInfo icp_info;
  const auto icp_pdf = registerMaps(icp, ref, cur, icp_info);
  const auto [icp_dt, icp_dr] = poseError(icp_pdf->getMeanVal(), truth_);

  CDirectHeightAligner dlo_aligner;
  CDirectHeightAligner::TReturnInfo info;
  const auto pdf = registerMaps(dlo_aligner, ref, cur, info);
  const auto [dt, dr] = poseError(pdf->getMeanVal(), truth_);
  std::printf("CICP: %.4f m %.4f deg in %.1f ms; DLO: %.4f m %.4f deg in %.1f ms\n", icp_dt, icp_dr,
              icp_info.executionTime * 1e3, dt, dr, info.executionTime * 1e3);

  ASSERT_TRUE(std::dynamic_pointer_cast<mrpt::poses::CPose3DPDFGaussian>(pdf));
  EXPECT_LT(dt, 0.03);
  EXPECT_LT(dr, 0.1);
}

TEST_F(RealScanAligner, FillsReturnInfo) {
  CDirectHeightAligner aligner;
  CDirectHeightAligner::TReturnInfo info;
  registerMaps(aligner, toPointsMap(even()), toPointsMap(test::expressIn(odd(), truth_)), info);
  EXPECT_GT(info.iterations, 0);
  EXPECT_GT(info.cells, aligner.options.params.solver.min_cells);
  EXPECT_GT(info.rms_height_error, 0.0);
  EXPECT_LT(info.rms_height_error, 0.2);
  EXPECT_TRUE(info.converged);
  EXPECT_FALSE(info.degenerate);
  EXPECT_GT(info.grid_ms, 0.0);
  EXPECT_GT(info.gradients_ms, 0.0);
  EXPECT_GT(info.selection_ms, 0.0);
  EXPECT_GT(info.solve_ms, 0.0);
  EXPECT_GE(info.executionTime * 1e3,
            info.grid_ms + info.gradients_ms + info.selection_ms + info.solve_ms);
}

TEST_F(RealScanAligner, BaseResultTypeGetsExecutionTime) {
  CDirectHeightAligner aligner;
  mrpt::slam::TMetricMapAlignmentResult info;
  registerMaps(aligner, toPointsMap(even()), toPointsMap(odd()), info);
  EXPECT_GT(info.executionTime, 0.0);
}

TEST_F(RealScanAligner, RecoversSixDofMotionWithCovarianceInMrptOrder) {
  const Eigen::Isometry3d truth =
      poseFromXYZYPR(0.5, -0.3, 0.05, 2 * kDeg, 0.5 * kDeg, -0.5 * kDeg);
  CDirectHeightAligner aligner;
  aligner.options.params.solver.dof = 6;
  CDirectHeightAligner::TReturnInfo info;
  const auto pdf =
      registerMaps(aligner, toPointsMap(even()), toPointsMap(test::expressIn(odd(), truth)), info);
  const auto [dt, dr] = poseError(pdf->getMeanVal(), truth);
  EXPECT_LT(dt, 0.03);
  EXPECT_LT(dr, 0.1);
  const auto& gauss = dynamic_cast<const mrpt::poses::CPose3DPDFGaussian&>(*pdf);
  // Every direction observed: small, positive variances, and symmetric.
  for (int i = 0; i < 6; ++i) {
    EXPECT_GT(gauss.cov(i, i), 0.0);
    EXPECT_LT(gauss.cov(i, i), 1e-2) << i;
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(gauss.cov(i, j), gauss.cov(j, i), 1e-12);
  }
}

TEST_F(RealScanAligner, ThreeDofLeavesZPitchRollAtTheGuessWithLargeVariance) {
  CDirectHeightAligner aligner;  // dof 3 by default
  mrpt::poses::CPose3DPDFGaussian guess;
  guess.mean = mrpt::poses::CPose3D(0.9, -0.4, 0.2, 4 * kDeg, 1 * kDeg, -2 * kDeg);
  const auto pdf = aligner.Align3DPDF(
      &static_cast<const mrpt::maps::CMetricMap&>(toPointsMap(even())),
      &static_cast<const mrpt::maps::CMetricMap&>(toPointsMap(test::expressIn(odd(), truth_))),
      guess);
  const auto& gauss = dynamic_cast<const mrpt::poses::CPose3DPDFGaussian&>(*pdf);
  EXPECT_NEAR(gauss.mean.z(), 0.2, 1e-9);
  EXPECT_NEAR(gauss.mean.pitch(), 1 * kDeg, 1e-9);
  EXPECT_NEAR(gauss.mean.roll(), -2 * kDeg, 1e-9);
  for (int unobserved : {2, 4, 5}) EXPECT_GT(gauss.cov(unobserved, unobserved), 1e3);
  // The unobserved variance must not leak into x, y, yaw through the guess's z, pitch, roll.
  for (int observed : {0, 1, 3}) {
    EXPECT_LT(gauss.cov(observed, observed), 1e-2);
    EXPECT_EQ(gauss.cov(observed, 2), 0.0);
  }
}

TEST_F(RealScanAligner, AlignPdfReturnsAnSe2Gaussian) {
  CDirectHeightAligner aligner;
  aligner.options.params.solver.dof = 6;  // SE(2) forces 3-DoF anyway
  const auto ref = toPointsMap(even());
  const auto cur = toPointsMap(test::expressIn(odd(), truth_));
  CDirectHeightAligner::TReturnInfo info;
  const auto pdf = aligner.AlignPDF(&ref, &cur, mrpt::poses::CPosePDFGaussian(), info);
  const auto gauss = std::dynamic_pointer_cast<mrpt::poses::CPosePDFGaussian>(pdf);
  ASSERT_TRUE(gauss);
  EXPECT_NEAR(gauss->mean.x(), 1.0, 0.03);
  EXPECT_NEAR(gauss->mean.y(), -0.5, 0.03);
  EXPECT_NEAR(gauss->mean.phi() / kDeg, 5.0, 0.1);
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(gauss->cov(i, i), 0.0);
    EXPECT_LT(gauss->cov(i, i), 1e-2);  // no unobserved direction in the SE(2) block
  }
  EXPECT_TRUE(info.converged);
}

TEST_F(RealScanAligner, AlignsCHeightGridMap2DInputs) {
  const auto ref = toHeightMap(even());
  const auto cur = toHeightMap(test::expressIn(odd(), truth_));
  CDirectHeightAligner aligner;
  CDirectHeightAligner::TReturnInfo info;
  const auto pdf = registerMaps(aligner, ref, cur, info);
  const auto [dt, dr] = poseError(pdf->getMeanVal(), truth_);
  std::printf("CHeightGridMap2D: %.4f m %.4f deg, %d cells\n", dt, dr, info.cells);
  EXPECT_LT(dt, 0.05);
  EXPECT_LT(dr, 0.2);
}

TEST_F(RealScanAligner, AlignsAPointsMapAgainstACHeightGridMap2D) {
  const auto ref = toHeightMap(even());
  const auto cur = toPointsMap(test::expressIn(odd(), truth_));
  CDirectHeightAligner aligner;
  CDirectHeightAligner::TReturnInfo info;
  const auto [dt, dr] = poseError(registerMaps(aligner, ref, cur, info)->getMeanVal(), truth_);
  EXPECT_LT(dt, 0.05);
  EXPECT_LT(dr, 0.2);
}

TEST(HeightGridMapConversion, KeepsMeanHeightCountAndPlacement) {
  mrpt::maps::CHeightGridMap2D map(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, -2, 2, -1, 1,
                                   0.5);
  for (double z : {1.0, 2.0, 6.0}) map.insertIndividualPoint(1.2, -0.7, z);
  map.insertIndividualPoint(-1.9, 0.9, 5.0);
  const HeightGrid grid = toHeightGrid(map, 3);
  EXPECT_EQ(grid.cols(), static_cast<int>(map.getSizeX()));
  EXPECT_EQ(grid.rows(), static_cast<int>(map.getSizeY()));
  const GridGeometry& g = grid.geometry();
  const int col = static_cast<int>(std::floor(g.u(1.2)));
  const int row = static_cast<int>(std::floor(g.v(-0.7)));
  EXPECT_TRUE(grid.isValid(row, col));
  EXPECT_FLOAT_EQ(grid.height(row, col), 3.0f);
  EXPECT_EQ(grid.count(row, col), 3u);
  EXPECT_EQ(grid.validCellCount(), 1);  // the single-point cell is below min_points
}

TEST(CDirectHeightAlignerMaps, RejectsUnsupportedMapClassNamingIt) {
  mrpt::maps::COccupancyGridMap2D grid(-5, 5, -5, 5, 0.1);
  mrpt::maps::CSimplePointsMap points;
  points.insertPoint(1, 2, 3);
  CDirectHeightAligner aligner;
  try {
    aligner.Align3DPDF(&points, &grid, mrpt::poses::CPose3DPDFGaussian());
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("COccupancyGridMap2D"), std::string::npos) << e.what();
  }
  EXPECT_THROW(aligner.AlignPDF(&grid, &points, mrpt::poses::CPosePDFGaussian()),
               std::invalid_argument);
  EXPECT_THROW(aligner.AlignPDF(nullptr, &points, mrpt::poses::CPosePDFGaussian()),
               std::invalid_argument);
}

TEST(CDirectHeightAlignerOptions, LoadFromConfigFileAndDumpRoundTrip) {
  CDirectHeightAligner a;
  mrpt::config::CConfigFileMemory ini("[DLO.solver]\ndof = 6\n[DLO.grid]\nresolution = 0.2\n");
  a.options.loadFromConfigFile(ini, "DLO");
  EXPECT_EQ(a.options.params.solver.dof, 6);
  EXPECT_DOUBLE_EQ(a.options.params.grid.resolution, 0.2);
  EXPECT_EQ(a.options.params.grid.cols, DloParams().grid.cols);

  std::ostringstream dump;
  a.options.dumpToTextStream(dump);
  EXPECT_NE(dump.str().find("[solver]"), std::string::npos);
  CDirectHeightAligner b;
  b.options.loadFromConfigFile(mrpt::config::CConfigFileMemory(dump.str()), "");
  EXPECT_EQ(dloParamsToIni(b.options.params), dloParamsToIni(a.options.params));
}

TEST(CDirectHeightAlignerOptions, BadValueThrowsInputErrorNamingTheKey) {
  CDirectHeightAligner a;
  mrpt::config::CConfigFileMemory ini("[solver]\nmax_iterations = 0\n");
  try {
    a.options.loadFromConfigFile(ini, "");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("solver.max_iterations"), std::string::npos);
  }
  EXPECT_EQ(a.options.params.solver.max_iterations, SolverParams().max_iterations);
}

}  // namespace
}  // namespace dlo
