/// \file CDirectHeightAligner.h
/// \brief DLO as an MRPT map aligner: a drop-in alternative to mrpt::slam::CICP.
#pragma once

#include <mrpt/config/CLoadableOptions.h>
#include <mrpt/maps/CMetricMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/slam/CMetricMapsAlignmentAlgorithm.h>
#include <ostream>
#include <string>

#include "dlo/core/dlo_params.h"
#include "dlo/core/height_frame.h"
#include "dlo/core/point_cloud.h"

namespace mrpt::slam {

/// Direct LiDAR Odometry registration of two 2.5D height maps, behind MRPT's
/// CMetricMapsAlignmentAlgorithm interface: code written for CICP works unchanged.
///
/// Inputs (m1 = reference, m2 = current) may be any mrpt::maps::CPointsMap (rasterised with
/// options.params.grid, centred on the map's origin) or an mrpt::maps::CHeightGridMap2D (its
/// cells are used as they are: mean height h and point count w). The result is the pose of m2 in
/// m1's frame, as for CICP, with the covariance of the Gauss-Newton solution.
///
/// Registered with MRPT's RTTI: `mrpt::rtti::classFactory("mrpt::slam::CDirectHeightAligner")`
/// creates one (call dlo::registerMrptClasses() first when linking dlo_mrpt statically).
class CDirectHeightAligner : public CMetricMapsAlignmentAlgorithm, public mrpt::rtti::CObject {
  DEFINE_MRPT_OBJECT(CDirectHeightAligner, mrpt::slam)

 public:
  /// The DLO parameters as MRPT loadable options.
  class TConfigParams : public mrpt::config::CLoadableOptions {
   public:
    dlo::DloParams params;  ///< every parameter, see dlo/core/dlo_params.h

    /// Reads sections [section.grid], [section.selection], [section.solver] (plain [grid], ...
    /// when `section` is empty); absent keys keep their current value.
    /// \throws dlo::InputError naming the key for a bad or unknown key or value.
    void loadFromConfigFile(const mrpt::config::CConfigFileBase& source,
                            const std::string& section) override;
    /// Writes every key into the sections loadFromConfigFile() reads.
    void saveToConfigFile(mrpt::config::CConfigFileBase& target,
                          const std::string& section) const override;
    /// Prints the parameters as commented INI text (sections [grid], [selection], [solver]).
    void dumpToTextStream(std::ostream& out) const override;
  };

  /// What one registration did, beyond the pose.
  struct TReturnInfo : public TMetricMapAlignmentResult {
    int iterations = 0;             ///< Gauss-Newton iterations over all pyramid levels
    int cells = 0;                  ///< cells with a valid residual at the last iteration
    double rms_height_error = 0.0;  ///< RMS height error at the end, metres
    bool degenerate = false;        ///< ill-conditioned Hessian or too few cells
    bool converged = false;         ///< the finest level met the step criteria
    /// Smallest over largest Hessian eigenvalue (rotations scaled to metres); near 0 means an
    /// unobservable direction (open field, corridor).
    double information_ratio = 0.0;
    double grid_ms = 0.0;       ///< rasterising both maps (pyramids, hole filling)
    double gradients_ms = 0.0;  ///< gradients and samplers of both maps
    double selection_ms = 0.0;  ///< cell selection of both maps
    double solve_ms = 0.0;      ///< Gauss-Newton, all levels
    // executionTime (inherited): whole call, seconds.
  };

  TConfigParams options;

  CDirectHeightAligner() = default;
  explicit CDirectHeightAligner(const dlo::DloParams& params) { options.params = params; }

  /// SE(2) registration: always 3-DoF (x, y, yaw), whatever options.params.solver.dof says.
  /// \return a CPosePDFGaussian: pose of m2 in m1, covariance of (x, y, yaw).
  /// \throws std::invalid_argument if a map is null or of an unsupported class.
  mrpt::poses::CPosePDF::Ptr AlignPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPosePDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<TMetricMapAlignmentResult> outInfo = std::nullopt) override;

  /// SE(3) registration with options.params.solver.dof degrees of freedom (3: z, pitch and roll
  /// stay at the initial guess; 6: all estimated).
  /// \return a CPose3DPDFGaussian: pose of m2 in m1, covariance of (x, y, z, yaw, pitch, roll).
  /// \throws std::invalid_argument if a map is null or of an unsupported class.
  mrpt::poses::CPose3DPDF::Ptr Align3DPDF(
      const mrpt::maps::CMetricMap* m1, const mrpt::maps::CMetricMap* m2,
      const mrpt::poses::CPose3DPDFGaussian& initialEstimationPDF,
      mrpt::optional_ref<TMetricMapAlignmentResult> outInfo = std::nullopt) override;

  /// The HeightFrame registration needs from a supported map, for a `dof` registration.
  /// \throws std::invalid_argument naming the class of an unsupported map.
  dlo::HeightFrame makeFrame(const mrpt::maps::CMetricMap& map, int dof) const;
  /// The HeightFrame of points given in the vehicle frame, for a `dof` registration.
  dlo::HeightFrame makeFrame(const dlo::PointCloud& points, int dof) const;

  /// The registration itself, on prepared frames: what AlignPDF/Align3DPDF call, and what a tool
  /// that reuses frames (odometry: each frame is current once and reference next) calls
  /// directly. Fills `info` (stage times include building both frames; executionTime is the
  /// sum of the stages).
  mrpt::poses::CPose3DPDFGaussian alignFrames(const dlo::HeightFrame& reference,
                                              const dlo::HeightFrame& current,
                                              const mrpt::poses::CPose3D& initial_guess, int dof,
                                              TReturnInfo& info) const;
};

}  // namespace mrpt::slam
