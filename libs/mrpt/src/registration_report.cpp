#include "dlo/mrpt/registration_report.h"

#include <cmath>

#include <sstream>
#include "dlo/core/json_text.h"

namespace dlo {

namespace {

/// A degenerate solve can produce NaN or infinity in the covariance: written as null.
std::string number(double v) {
  return jsonNumber(v, 17);
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
