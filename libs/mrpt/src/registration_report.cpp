#include "dlo/mrpt/registration_report.h"

#include <cmath>
#include <sstream>

namespace dlo {

namespace {

/// JSON has no NaN or infinity; a degenerate solve can produce them in the covariance.
std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

std::string registrationReportJson(const mrpt::poses::CPose3DPDFGaussian& pdf,
                                   const mrpt::slam::CDirectHeightAligner::TReturnInfo& info) {
  constexpr double kDeg = 180.0 / M_PI;
  const mrpt::poses::CPose3D& p = pdf.mean;
  std::ostringstream out;
  out << "{\"pose\": {\"x\": " << number(p.x()) << ", \"y\": " << number(p.y())
      << ", \"z\": " << number(p.z()) << ", \"yaw_deg\": " << number(p.yaw() * kDeg)
      << ", \"pitch_deg\": " << number(p.pitch() * kDeg)
      << ", \"roll_deg\": " << number(p.roll() * kDeg) << "}, \"covariance\": [";
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) out << (r + c > 0 ? ", " : "") << number(pdf.cov(r, c));
  out << "], \"iterations\": " << info.iterations << ", \"cells\": " << info.cells
      << ", \"rms_height_error\": " << number(info.rms_height_error)
      << ", \"degenerate\": " << (info.degenerate ? "true" : "false")
      << ", \"converged\": " << (info.converged ? "true" : "false")
      << ", \"information_ratio\": " << number(info.information_ratio)
      << ", \"time_ms\": {\"grid\": " << number(info.grid_ms)
      << ", \"gradients\": " << number(info.gradients_ms)
      << ", \"selection\": " << number(info.selection_ms)
      << ", \"solve\": " << number(info.solve_ms)
      << ", \"total\": " << number(info.executionTime * 1e3) << "}}";
  return out.str();
}

}  // namespace dlo
