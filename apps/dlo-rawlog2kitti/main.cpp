// dlo-rawlog2kitti: writes the scans of an MRPT rawlog as a KITTI odometry sequence folder (and
// the ground truth as its poses.txt), for programs that read KITTI folders.
#include <iostream>
#include <limits>
#include <optional>
#include <string>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/app/scan_input_options.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/kitti_conversion.h"

namespace {

constexpr const char* kDescription =
    "Writes the scans of an MRPT rawlog as a KITTI odometry sequence folder, one scan in memory "
    "at a time, for programs that read KITTI folders (other odometries, their evaluation tools).";

constexpr const char* kFooter =
    R"(The scans are those dlo-slam and dlo-bench read from IN: every supported observation, points
in the VEHICLE frame (the observation's sensorPose applied), non-finite points dropped.
OUT_DIR (new, or an empty folder) receives:
  velodyne/000000.bin, ...   float32 x, y, z, intensity per point (intensity is 0: DLO's scans
                             keep none); per-point times are not kept;
  times.txt                  the scans' timestamps in seconds, as in the rawlog (not restarted
                             at 0, so that trajectories stamped with them match GT.tum);
  poses.txt                  with --gt: the ground-truth pose stamped nearest each scan (within
                             5 ms), as a row-major 3x4 matrix in the first scan's frame. There is
                             no calib.txt: the poses are those of the frame the points are in.
dlo-kitti2rawlog and dlo-slam --input OUT_DIR read the folder back as the same scans. The folder
is built as OUT_DIR.tmp and renamed at the end, so OUT_DIR is complete or absent.

Exit status: 0 on success, 1 for a bad input (a rawlog that breaks part way: the scans before
the break are written and the break is reported), 2 for a command-line error; errors are one
line on stderr starting with "dlo-rawlog2kitti: ".)";

using dlo::UsageError;

struct Arguments {
  std::string rawlog, out, gt;
  dlo::ScanInputOptions scans;
  bool quiet = false;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-rawlog2kitti", kDescription);
  cl.positional("IN.rawlog", a.rawlog, "the rawlog to read").required();
  cl.positional("OUT_DIR", a.out, "the KITTI folder to write (see below)").required();
  cl.text("--gt", a.gt, "TUM ground truth of IN (\"t x y z qx qy qz qw\"), written as poses.txt")
      .valueName("FILE");
  // Every point by default: the folder is a copy of the rawlog's scans.
  a.scans.min_range = 0.0;
  a.scans.max_range = std::numeric_limits<double>::infinity();
  dlo::declareScanInputOptions(cl, a.scans, dlo::kScanMaxFrames | dlo::kScanRange);
  cl.flag("--quiet", a.quiet, "no progress and no summary");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (cl.given("--gt") && a.gt.empty()) throw UsageError{"--gt needs a file name."};
  dlo::checkScanInputOptions(a.scans);
  return a;
}

int run(const Arguments& args) {
  dlo::ProgressBar bar(args.scans.max_frames > 0 ? static_cast<size_t>(args.scans.max_frames) : 0,
                       "scans", !args.quiet);
  const dlo::RawlogToKittiResult r = dlo::convertRawlogToKitti(
      args.rawlog, args.out, args.gt,
      dlo::ScanSourceOptions{args.scans.min_range, args.scans.max_range, {}}, args.scans.max_frames,
      [&](size_t done) { bar.update(done); });
  bar.finish(r.scans);
  if (!args.quiet) {
    std::cout << "wrote " << r.scans << " scans (" << r.points << " points) to '" << args.out
              << "'";
    if (r.poses > 0)
      std::cout << " with " << r.poses << " ground-truth poses from '" << args.gt << "'";
    std::cout << ".\n" << dlo::describeScanSourceStats(r.stats);
  }
  if (!r.input_warning.empty()) {
    std::cerr << "dlo-rawlog2kitti: '" << args.rawlog << "' breaks after " << r.scans
              << " scans (written): " << r.input_warning << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-rawlog2kitti", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
