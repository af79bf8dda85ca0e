// dlo-kitti2rawlog: converts a KITTI odometry sequence folder into an MRPT rawlog (and TUM
// ground truth).
#include <iostream>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/command_line.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/kitti_conversion.h"

namespace {

constexpr const char* kUsage =
    R"(Usage: dlo-kitti2rawlog SEQ_DIR OUT.rawlog [--gt OUT_GT.tum] [--quiet] [--help]

Converts a KITTI odometry sequence folder into an MRPT rawlog, one scan in memory at a time.

SEQ_DIR holds:
  velodyne/*.bin or *.bin.gz   the scans (float32 x, y, z, reflectance), taken in name order;
  times.txt                    optional, one time in seconds per scan (missing: 10 Hz);
  poses.txt                    optional, one row-major 3x4 pose per scan (needed for --gt);
  calib.txt                    optional; its 'Tr:' line (LiDAR to camera) turns KITTI's camera
                               poses into LiDAR poses: T_velo = Tr^-1 * P_cam * Tr. Without it,
                               poses.txt is taken to hold LiDAR poses already.

Output: OUT.rawlog (OUT.rawlog.gz is gzip-compressed), observation-only layout, one
CObservationPointCloud per scan: CPointsMapXYZI with reflectance as intensity, sensorLabel
"VELODYNE", identity sensorPose (KITTI points are in the LiDAR frame). Written to OUT.tmp and
renamed at the end, so an existing OUT is never half-overwritten.

Options:
  --gt FILE   also write the ground truth, LiDAR frame, as TUM lines "t x y z qx qy qz qw".
  --quiet     no progress bar and no summary.
  --help      prints this text.

Exit status: 0 on success, 1 for a bad input (the scans converted before the bad one are kept
in OUT.partial), 2 for a command-line error; errors are one line on stderr starting with
"dlo-kitti2rawlog: ".
)";

using dlo::UsageError;

struct Arguments {
  std::string seq_dir;
  std::string out;
  std::string gt;
  bool quiet = false;
  bool help = false;
};

Arguments parseArguments(int argc, char** argv) {
  const dlo::CommandLine cl(argc, argv, {"--gt"}, {"--quiet"});
  Arguments a;
  a.help = cl.help();
  if (a.help) return a;
  const auto gt = cl.value("--gt");
  if (gt && gt->empty()) throw UsageError{"--gt needs a file name."};
  a.gt = cl.text("--gt");
  a.quiet = cl.flag("--quiet");
  if (cl.positional().size() != 2) {
    throw UsageError{"expected SEQ_DIR and OUT.rawlog, got " +
                     std::to_string(cl.positional().size()) + " arguments (see --help)."};
  }
  a.seq_dir = cl.positional()[0];
  a.out = cl.positional()[1];
  return a;
}

int run(const Arguments& args) {
  dlo::ProgressBar bar(0, "scans", !args.quiet);
  const dlo::KittiConversionResult r =
      dlo::convertKittiSequence(args.seq_dir, args.out, args.gt, [&](size_t done, size_t total) {
        bar.setTotal(total);
        bar.update(done);
      });
  bar.finish(r.scans);
  if (!args.quiet) {
    std::cout << "wrote " << r.scans << " scans (" << r.points << " points) to '" << args.out
              << "'";
    if (!r.times_from_file) std::cout << "; no times.txt, 10 Hz assumed";
    if (r.dropped_non_finite > 0) {
      std::cout << "; dropped " << r.dropped_non_finite << " non-finite points";
    }
    if (r.empty_scans > 0) std::cout << "; " << r.empty_scans << " scans are empty";
    if (!args.gt.empty()) {
      std::cout << "; ground truth (" << r.poses << " poses, LiDAR frame"
                << (r.poses_from_camera_frame ? ", converted from the camera frame with calib.txt"
                                              : ", poses.txt taken as LiDAR poses")
                << ") to '" << args.gt << "'";
    }
    std::cout << ".\n";
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-kitti2rawlog", [&] {
    const Arguments args = parseArguments(argc, argv);
    if (args.help) {
      std::cout << kUsage;
      return 0;
    }
    return run(args);
  });
}
