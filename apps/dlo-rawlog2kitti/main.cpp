// dlo-rawlog2kitti: writes the scans of an MRPT rawlog as a KITTI odometry sequence folder (and
// the ground truth as its poses.txt), for programs that read KITTI folders.
#include <iostream>
#include <string>

#include "dlo/app/app_main.h"
#include "dlo/app/command_line.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/kitti_conversion.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: dlo-rawlog2kitti IN.rawlog OUT_DIR [--gt GT.tum] [--max-frames N]
                        [--min-range M] [--max-range M] [--quiet] [--help]

Writes the scans of an MRPT rawlog as a KITTI odometry sequence folder, one scan in memory at a
time, for programs that read KITTI folders (other odometries, their evaluation tools).

The scans are those dlo-slam and dlo-bench read from IN: every supported observation, points
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

Options:
  --gt FILE        TUM ground truth of IN ("t x y z qx qy qz qw"), written as poses.txt.
  --max-frames N   only the first N scans.
  --min-range M    drop points closer than M metres to the sensor (default 0).
  --max-range M    drop points farther than M metres (default: none).
  --quiet          no progress and no summary.
  --help           print this text.

Exit status: 0 on success, 1 for a bad input (a rawlog that breaks part way: the scans before
the break are written and the break is reported), 2 for a command-line error; errors are one
line on stderr starting with "dlo-rawlog2kitti: ".
)";

using dlo::UsageError;

struct Arguments {
  std::string rawlog, out, gt;
  long max_frames = -1;
  dlo::ScanSourceOptions options;
  bool quiet = false, help = false;
};

Arguments parseArguments(int argc, char** argv) {
  const dlo::CommandLine cl(argc, argv, {"--gt", "--max-frames", "--min-range", "--max-range"},
                            {"--quiet"});
  Arguments a;
  a.help = cl.help();
  if (a.help) return a;
  const auto gt = cl.value("--gt");
  if (gt && gt->empty()) throw UsageError{"--gt needs a file name."};
  a.gt = cl.text("--gt");
  a.quiet = cl.flag("--quiet");
  a.max_frames = cl.integer("--max-frames", a.max_frames);
  if (cl.value("--max-frames") && a.max_frames < 1) {
    throw UsageError{"--max-frames expects a whole number of scans >= 1."};
  }
  a.options.min_range = cl.number("--min-range", a.options.min_range);
  a.options.max_range = cl.number("--max-range", a.options.max_range);
  if (!(a.options.min_range >= 0.0 && a.options.max_range > a.options.min_range)) {
    throw UsageError{"--min-range and --max-range must satisfy 0 <= min < max."};
  }
  if (cl.positional().size() != 2) {
    throw UsageError{"expected IN.rawlog and OUT_DIR, got " +
                     std::to_string(cl.positional().size()) + " arguments (see --help)."};
  }
  a.rawlog = cl.positional()[0];
  a.out = cl.positional()[1];
  return a;
}

int run(const Arguments& args) {
  dlo::ProgressBar bar(args.max_frames > 0 ? static_cast<size_t>(args.max_frames) : 0, "scans",
                       !args.quiet);
  const dlo::RawlogToKittiResult r =
      dlo::convertRawlogToKitti(args.rawlog, args.out, args.gt, args.options, args.max_frames,
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
    const Arguments args = parseArguments(argc, argv);
    if (args.help) {
      std::cout << kUsage;
      return 0;
    }
    return run(args);
  });
}
