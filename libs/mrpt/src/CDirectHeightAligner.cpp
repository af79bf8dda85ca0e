#include "dlo/mrpt/CDirectHeightAligner.h"

#include <mrpt/core/initializer.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/CPointsMap.h>
#include <stdexcept>

#include "dlo/core/direct_aligner.h"
#include "dlo/core/rigid_transform.h"
#include "dlo/core/stage_times.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/mrpt/height_grid_map_conversion.h"
#include "dlo/mrpt/point_conversion.h"
#include "dlo/mrpt/pose_conversion.h"

IMPLEMENTS_MRPT_OBJECT(CDirectHeightAligner, mrpt::rtti::CObject, mrpt::slam)

// Registration at load time, for programs that use the class at all: this object file is then
// linked. Programs that only name the class as a string call dlo::registerMrptClasses().
MRPT_INITIALIZER(dlo_mrpt_register_classes) {
  mrpt::rtti::registerClass(CLASS_ID(mrpt::slam::CDirectHeightAligner));
}

namespace mrpt::slam {

namespace {

const mrpt::maps::CMetricMap& required(const mrpt::maps::CMetricMap* map, const char* which) {
  if (!map) {
    throw std::invalid_argument(std::string("CDirectHeightAligner: map ") + which + " is null.");
  }
  return *map;
}

/// Fills the DLO fields of `out` when the caller passed a TReturnInfo; other result types only
/// get executionTime, as the base interface promises.
void report(const CDirectHeightAligner::TReturnInfo& info,
            mrpt::optional_ref<TMetricMapAlignmentResult> out) {
  if (!out) return;
  TMetricMapAlignmentResult& target = out->get();
  if (auto* full = dynamic_cast<CDirectHeightAligner::TReturnInfo*>(&target)) {
    *full = info;
  } else {
    target.executionTime = info.executionTime;
  }
}

/// The covariance of MRPT's (x, y, z, yaw, pitch, roll) for a core result.
/// A 3-DoF solve leaves z, pitch and roll exactly at the guess (left updates by (tx, ty, wz) do
/// not change them), but the core reports the unobserved twist directions (tz, wx, wy) with a huge
/// variance; linearised around a pose with z != 0, a left rotation wx/wy moves x and y, so that
/// variance would leak into x and y. Convert the observed block alone and put the unobserved
/// variance on z, pitch and roll, where it belongs in MRPT's parameters.
dlo::Matrix6d mrptCovariance(const dlo::AlignmentResult& r, int dof) {
  if (dof == 6) return dlo::twistCovarianceToXYZYPR(r.pose, r.covariance);
  constexpr int kObserved[3] = {0, 1, 5};  // tx, ty, wz
  dlo::Matrix6d observed = dlo::Matrix6d::Zero();
  for (int i : kObserved)
    for (int j : kObserved) observed(i, j) = r.covariance(i, j);
  dlo::Matrix6d cov = dlo::twistCovarianceToXYZYPR(r.pose, observed);
  const double unobserved = r.covariance(2, 2);
  for (int i : {2, 4, 5}) cov(i, i) = unobserved;  // z, pitch, roll
  return cov;
}

}  // namespace

void CDirectHeightAligner::TConfigParams::loadFromConfigFile(
    const mrpt::config::CConfigFileBase& source, const std::string& section) {
  params = dlo::loadDloParams(source, section, params);
}

void CDirectHeightAligner::TConfigParams::saveToConfigFile(mrpt::config::CConfigFileBase& target,
                                                           const std::string& section) const {
  dlo::saveDloParams(params, target, section);
}

void CDirectHeightAligner::TConfigParams::dumpToTextStream(std::ostream& out) const {
  out << dlo::dloParamsToIni(params);
}

dlo::HeightFrame CDirectHeightAligner::makeFrame(const dlo::PointCloud& points, int dof) const {
  const dlo::DloParams& p = options.params;
  return dlo::HeightFrame::fromPoints(points, p.grid, p.selection, dof == 6);
}

dlo::HeightFrame CDirectHeightAligner::makeFrame(const mrpt::maps::CMetricMap& map, int dof) const {
  if (const auto* points = dynamic_cast<const mrpt::maps::CPointsMap*>(&map)) {
    return makeFrame(dlo::toPointCloud(*points), dof);
  }
  if (const auto* heights = dynamic_cast<const mrpt::maps::CHeightGridMap2D*>(&map)) {
    const dlo::DloParams& p = options.params;
    const dlo::HeightGrid grid = dlo::toHeightGrid(*heights, p.grid.min_points);
    // A small map cannot hold as many levels as the configured window: stop where the coarsest
    // level would drop below 4 cells on a side, the same limit DloParams::validate() enforces.
    int levels = p.grid.levels;
    while (levels > 1 && ((grid.cols() >> (levels - 1)) < 4 || (grid.rows() >> (levels - 1)) < 4))
      --levels;
    return dlo::HeightFrame::fromGrid(grid, levels, p.selection, dof == 6);
  }
  throw std::invalid_argument(std::string("CDirectHeightAligner: map class '") +
                              map.GetRuntimeClass()->className +
                              "' is not supported: expected an mrpt::maps::CPointsMap or "
                              "mrpt::maps::CHeightGridMap2D.");
}

mrpt::poses::CPose3DPDFGaussian CDirectHeightAligner::alignFrames(
    const dlo::HeightFrame& reference, const dlo::HeightFrame& current,
    const mrpt::poses::CPose3D& initial_guess, int dof, TReturnInfo& info) const {
  dlo::SolverParams solver = options.params.solver;
  solver.dof = dof;
  const dlo::AlignmentResult r =
      dlo::DirectAligner(solver).align(reference, current, dlo::toIsometry(initial_guess));

  dlo::StageTimes times = reference.buildTimes();
  times += current.buildTimes();
  times.solve_ms += r.times.solve_ms;
  info.iterations = r.iterations;
  info.cells = r.cells;
  info.rms_height_error = r.rms_height_error;
  info.degenerate = r.degenerate;
  info.converged = r.converged;
  info.information_ratio = r.information_ratio;
  info.grid_ms = times.grid_ms;
  info.gradients_ms = times.gradients_ms;
  info.selection_ms = times.selection_ms;
  info.solve_ms = times.solve_ms;
  info.executionTime = times.totalMs() * 1e-3;

  mrpt::poses::CPose3DPDFGaussian pdf;
  pdf.mean = dlo::toCPose3D(r.pose);
  pdf.cov = mrpt::math::CMatrixDouble66(mrptCovariance(r, dof));
  return pdf;
}

mrpt::poses::CPose3DPDF::Ptr CDirectHeightAligner::Align3DPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
    mrpt::optional_ref<TMetricMapAlignmentResult> outInfo) {
  dlo::Stopwatch sw;
  const int dof = options.params.solver.dof;
  const dlo::HeightFrame reference = makeFrame(required(m1, "m1 (reference)"), dof);
  const dlo::HeightFrame current = makeFrame(required(m2, "m2 (current)"), dof);
  TReturnInfo info;
  auto pdf = std::make_shared<mrpt::poses::CPose3DPDFGaussian>(
      alignFrames(reference, current, initialEstimationPDF.mean, dof, info));
  info.executionTime = sw.elapsedMs() * 1e-3;
  report(info, outInfo);
  return pdf;
}

mrpt::poses::CPosePDF::Ptr CDirectHeightAligner::AlignPDF(
    const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
    const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
    mrpt::optional_ref<TMetricMapAlignmentResult> outInfo) {
  dlo::Stopwatch sw;
  constexpr int kDof = 3;
  const dlo::HeightFrame reference = makeFrame(required(m1, "m1 (reference)"), kDof);
  const dlo::HeightFrame current = makeFrame(required(m2, "m2 (current)"), kDof);
  TReturnInfo info;
  const mrpt::poses::CPose3DPDFGaussian pdf3 =
      alignFrames(reference, current, mrpt::poses::CPose3D(initialEstimationPDF.mean), kDof, info);
  info.executionTime = sw.elapsedMs() * 1e-3;
  report(info, outInfo);

  // (x, y, yaw) are entries 0, 1, 3 of MRPT's (x, y, z, yaw, pitch, roll).
  auto pdf = std::make_shared<mrpt::poses::CPosePDFGaussian>();
  pdf->mean = mrpt::poses::CPose2D(pdf3.mean);
  const int idx[3] = {0, 1, 3};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) pdf->cov(i, j) = pdf3.cov(idx[i], idx[j]);
  return pdf;
}

}  // namespace mrpt::slam
