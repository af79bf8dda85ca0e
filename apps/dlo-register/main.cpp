// dlo-register: registers one scan against another with DLO and prints the result as JSON.
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/core/stage_times.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/CDirectHeightAligner.h"
#include "dlo/mrpt/dlo_config.h"
#include "dlo/mrpt/registration_report.h"
#include "dlo/mrpt/scan_file.h"

namespace {

constexpr const char* kDescription =
    "Registers the scan CUR against the scan REF with Direct LiDAR Odometry and prints one JSON "
    "object on stdout: the pose of CUR in REF's frame and its covariance.";

constexpr const char* kFooter =
    R"(Scans: KITTI .bin / .bin.gz, .ply, or an MRPT .rawlog / .rawlog.gz (its first point cloud).

Output:
  {"pose": {"x", "y", "z" (metres), "yaw_deg", "pitch_deg", "roll_deg" (degrees)},
   "covariance": [36 numbers, row-major, order x y z yaw pitch roll; metres and RADIANS,
                  as MRPT's CPose3DPDFGaussian],
   "iterations", "cells", "rms_height_error" (metres), "degenerate", "converged",
   "information_ratio" (smallest / largest Hessian eigenvalue; near 0: degenerate scene),
   "time_ms": {"grid", "gradients", "selection", "solve", "total"}}
  Times cover building both height frames and the solve, not reading the files.

Exit status: 0 on success, 1 for a bad input file or parameter, 2 for a command-line error;
errors are one line on stderr starting with "dlo-register: ".)";

using dlo::UsageError;

struct Arguments {
  std::string ref;
  std::string cur;
  std::optional<int> dof;
  mrpt::poses::CPose3D init;
  std::string config;
  std::vector<std::string> sets;
};

int parseDof(const std::string& text) {
  if (text == "3") return 3;
  if (text == "6") return 6;
  throw UsageError{"--dof must be 3 or 6, got '" + text + "'."};
}

mrpt::poses::CPose3D parseInit(const std::string& text) {
  std::istringstream in(text);
  double v[6];
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) {
      throw UsageError{
          "--init expects six numbers \"x y z yaw pitch roll\" (metres, degrees), "
          "got '" +
          text + "'."};
    }
  }
  std::string rest;
  if (in >> rest) {
    throw UsageError{
        "--init expects six numbers \"x y z yaw pitch roll\" (metres, degrees), "
        "got '" +
        text + "'."};
  }
  constexpr double kRad = M_PI / 180.0;
  return mrpt::poses::CPose3D(v[0], v[1], v[2], v[3] * kRad, v[4] * kRad, v[5] * kRad);
}

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  std::string dof, init;
  dlo::ProgramOptions cl("dlo-register", kDescription);
  cl.positional("REF", a.ref, "the reference scan").required();
  cl.positional("CUR", a.cur, "the scan to register against REF").required();
  cl.text("--dof", dof,
          "degrees of freedom: 3 = x, y, yaw (z, pitch, roll stay at --init); 6 = full SE(3). "
          "Overrides solver.dof of --config and --set")
      .valueName("3|6");
  cl.text("--init", init, "initial guess of CUR in REF: metres and DEGREES (default: identity)")
      .valueName("\"x y z yaw pitch roll\"");
  cl.text("--config", a.config,
          "MRPT INI file with sections [grid], [selection], [solver]; keys are named like the "
          "fields of dlo::DloParams")
      .valueName("FILE");
  cl.repeatable("--set", a.sets, "overrides one parameter after --config; may be repeated")
      .valueName("section.key=value");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (cl.given("--dof")) a.dof = parseDof(dof);
  if (cl.given("--init")) a.init = parseInit(init);
  return a;
}

int run(const Arguments& args) {
  dlo::DloParams params =
      args.config.empty() ? dlo::DloParams() : dlo::loadDloParamsFile(args.config);
  dlo::applyDloParamOverrides(params, args.sets);
  if (args.dof) params.solver.dof = *args.dof;

  const dlo::PointCloud ref = dlo::loadScanFile(args.ref);
  const dlo::PointCloud cur = dlo::loadScanFile(args.cur);

  // Straight to the frames rather than through Align3DPDF: copying 100k+ points into
  // CSimplePointsMaps and back would cost more than rasterising them.
  mrpt::slam::CDirectHeightAligner aligner(params);
  mrpt::slam::CDirectHeightAligner::TReturnInfo info;
  const dlo::Stopwatch sw;
  const int dof = params.solver.dof;
  const mrpt::poses::CPose3DPDFGaussian pdf = aligner.alignFrames(
      aligner.makeFrame(ref, dof), aligner.makeFrame(cur, dof), args.init, dof, info);
  info.executionTime = sw.elapsedMs() * 1e-3;
  std::cout << dlo::registrationReportJson(pdf, info) << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-register", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
