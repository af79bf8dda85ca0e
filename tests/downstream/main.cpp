// Registers a synthetic scene against a copy moved by a known motion through the installed
// mrpt::slam::CDirectHeightAligner, as a user's program would; exits 1 if the motion is not
// recovered to within 8 cm and 0.5 deg.
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <dlo/mrpt/CDirectHeightAligner.h>
#include <cmath>
#include <cstdio>

namespace {

/// Flat ground with boxes of several heights and a wall, sampled every 5 cm.
mrpt::maps::CSimplePointsMap scene(const mrpt::poses::CPose3D& move) {
  mrpt::maps::CSimplePointsMap map;
  const auto add = [&](double x, double y, double z) {
    const mrpt::math::TPoint3D p = move.inverseComposePoint(mrpt::math::TPoint3D(x, y, z));
    map.insertPoint(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
  };
  for (double x = -15.0; x <= 15.0; x += 0.05) {
    for (double y = -15.0; y <= 15.0; y += 0.05) {
      double z = 0.0;
      if (std::abs(x - 4.0) < 1.0 && std::abs(y - 3.0) < 1.5) z = 1.2;
      if (std::abs(x + 6.0) < 0.8 && std::abs(y + 5.0) < 0.8) z = 2.0;
      if (std::abs(x - 1.0) < 2.5 && std::abs(y + 8.0) < 0.6) z = 0.6;
      if (std::abs(x + 9.0) < 0.2 && std::abs(y) < 8.0) z = 3.0;
      add(x, y, z);
    }
  }
  return map;
}

}  // namespace

int main() {
  const mrpt::poses::CPose3D truth(0.6, -0.3, 0.0, 3.0 * M_PI / 180.0, 0.0, 0.0);
  const mrpt::maps::CSimplePointsMap reference = scene(mrpt::poses::CPose3D());
  const mrpt::maps::CSimplePointsMap current = scene(truth);

  mrpt::slam::CDirectHeightAligner dlo;
  mrpt::slam::CDirectHeightAligner::TReturnInfo info;
  const mrpt::poses::CPose3DPDF::Ptr pdf = dlo.Align3DPDF(
      &reference, &current, mrpt::poses::CPose3DPDFGaussian(mrpt::poses::CPose3D()), info);
  if (!pdf) {
    std::fprintf(stderr, "dlo_downstream: the registration returned no pose\n");
    return 1;
  }
  const mrpt::poses::CPose3D found = pdf->getMeanVal();
  const double position_error = (found.translation() - truth.translation()).norm();
  const double yaw_error = std::abs(found.yaw() - truth.yaw()) * 180.0 / M_PI;
  std::printf("dlo_downstream: found (%.3f, %.3f, %.2f deg), truth (%.3f, %.3f, %.2f deg)\n",
              found.x(), found.y(), found.yaw() * 180.0 / M_PI, truth.x(), truth.y(),
              truth.yaw() * 180.0 / M_PI);
  return position_error < 0.08 && yaw_error < 0.5 ? 0 : 1;
}
