// dlo-kitti2rawlog: converts a KITTI odometry sequence folder into an MRPT rawlog (and TUM
// ground truth).
#include <iostream>
#include <string>
#include <vector>

#include "dlo/mrpt/app_main.h"
#include "dlo/mrpt/input_error.h"
#include "dlo/mrpt/kitti_conversion.h"
#include "dlo/mrpt/progress_bar.h"

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
  Arguments a;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      a.help = true;
      return a;
    }
    if (arg.rfind("--", 0) != 0 || arg == "--") {
      positional.push_back(arg);
      continue;
    }
    // Both "--opt value" and "--opt=value".
    std::string value;
    const auto eq = arg.find('=');
    if (eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
    } else if (arg == "--gt") {
      if (i + 1 >= argc) throw UsageError{arg + " needs a value."};
      value = argv[++i];
    }
    if (arg == "--gt") {
      if (value.empty()) throw UsageError{"--gt needs a file name."};
      a.gt = value;
    } else if (arg == "--quiet") {
      a.quiet = true;
    } else {
      throw UsageError{"unknown option '" + arg + "' (see --help)."};
    }
  }
  if (positional.size() != 2) {
    throw UsageError{"expected SEQ_DIR and OUT.rawlog, got " + std::to_string(positional.size()) +
                     " arguments (see --help)."};
  }
  a.seq_dir = positional[0];
  a.out = positional[1];
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
