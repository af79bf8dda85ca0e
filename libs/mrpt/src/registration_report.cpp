#include "dlo/mrpt/registration_report.h"

#include <cmath>

#include <nlohmann/json.hpp>

namespace dlo {

std::string registrationReportJson(const mrpt::poses::CPose3DPDFGaussian& pdf,
                                   const mrpt::slam::CDirectHeightAligner::TReturnInfo& info) {
  // The keys stay in the order written, the order scripts know.
  using Json = nlohmann::ordered_json;
  constexpr double kDegPerRad = 180.0 / M_PI;
  const mrpt::poses::CPose3D& p = pdf.mean;
  // A degenerate solve can produce NaN or infinity in the covariance: nlohmann writes null.
  Json covariance = Json::array();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) covariance.push_back(pdf.cov(r, c));
  const Json report = {{"pose",
                        {{"x", p.x()},
                         {"y", p.y()},
                         {"z", p.z()},
                         {"yaw_deg", p.yaw() * kDegPerRad},
                         {"pitch_deg", p.pitch() * kDegPerRad},
                         {"roll_deg", p.roll() * kDegPerRad}}},
                       {"covariance", std::move(covariance)},
                       {"iterations", info.iterations},
                       {"cells", info.cells},
                       {"rms_height_error", info.rms_height_error},
                       {"degenerate", info.degenerate},
                       {"converged", info.converged},
                       {"information_ratio", info.information_ratio},
                       {"time_ms",
                        {{"grid", info.grid_ms},
                         {"gradients", info.gradients_ms},
                         {"selection", info.selection_ms},
                         {"solve", info.solve_ms},
                         {"total", info.executionTime * 1e3}}}};
  return report.dump();
}

}  // namespace dlo
