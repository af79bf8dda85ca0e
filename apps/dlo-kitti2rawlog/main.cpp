// dlo-kitti2rawlog: converts a KITTI odometry sequence folder into an MRPT rawlog (and TUM
// ground truth).
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/mrpt/kitti_conversion.h"

namespace {

constexpr const char* kDescription =
    "Converts a KITTI odometry sequence folder into an MRPT rawlog, one scan in memory at a "
    "time.";

constexpr const char* kFooter = R"(SEQ_DIR holds:
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

Exit status: 0 on success, 1 for a bad input (the scans converted before the bad one are kept
in OUT.partial), 2 for a command-line error; errors are one line on stderr starting with
"dlo-kitti2rawlog: ".)";

using dlo::UsageError;

struct Arguments {
  std::string seq_dir;
  std::string out;
  std::string gt;
  bool quiet = false;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-kitti2rawlog", kDescription);
  cl.positional("SEQ_DIR", a.seq_dir, "the KITTI sequence folder (see below)").required();
  cl.positional("OUT.rawlog", a.out, "the rawlog to write").required();
  cl.text("--gt", a.gt,
          "also write the ground truth, LiDAR frame, as TUM lines \"t x y z qx qy qz qw\"")
      .valueName("FILE");
  cl.flag("--quiet", a.quiet, "no progress bar and no summary");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (cl.given("--gt") && a.gt.empty()) throw UsageError{"--gt needs a file name."};
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
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
