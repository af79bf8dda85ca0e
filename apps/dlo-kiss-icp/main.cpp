// dlo-kiss-icp: KISS-ICP's odometry (Vizzo et al., RA-L 2023; its C++ pipeline, built from the
// source tree the build was configured with) over the scans dlo-slam reads, poses written for
// dlo-bench --peer and scripts/eval_matrix.py --peer.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/progress_bar.h"
#include "dlo/files/error.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/kitti_scan_source.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "kiss_icp/pipeline/KissICP.hpp"

namespace {

constexpr const char* kDescription =
    "Runs KISS-ICP's odometry (its C++ pipeline, kiss_icp::pipeline::KissICP, from the source "
    "tree this build was configured with: cmake -DDLO_KISS_ICP_SOURCE=...) over the scans of IN "
    "and writes one pose per scan to OUT_POSES: KITTI format (a row-major 3x4 matrix per line, "
    "the first scan's frame), or TUM with --tum. IN is a KITTI folder (velodyne/*.bin[.gz], "
    "times.txt) or an MRPT rawlog, read as dlo-slam reads them. One thread; no deskewing (scans "
    "without per-point times, as most KITTI-format data).";

constexpr const char* kFooter =
    R"(Use it as a peer of dlo-bench or scripts/eval_matrix.py:
  --peer "KISS-ICP=build/apps/dlo-kiss-icp/dlo-kiss-icp {kitti} {out}"

Exit status: 0 on success, 1 for a bad input (a file that breaks part way: the poses of the
scans before it are written), 2 for a command-line error.)";

using dlo::UsageError;

struct Arguments {
  std::string in, out;
  double max_range = 100.0, min_range = 0.0, voxel = -1.0;
  long max_frames = -1;
  bool tum = false, quiet = false;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  dlo::ProgramOptions cl("dlo-kiss-icp", kDescription);
  cl.positional("IN", a.in, "a KITTI folder or an MRPT rawlog").required();
  cl.positional("OUT_POSES", a.out, "the poses to write").required();
  cl.number("--max-range", a.max_range, "KISS-ICP's max_range, metres (its default)")
      .valueName("M");
  cl.number("--min-range", a.min_range, "KISS-ICP's min_range, metres (its default)")
      .valueName("M");
  cl.number("--voxel", a.voxel,
            "KISS-ICP's voxel_size, metres (default: max range / 100, as its own pipeline "
            "chooses)")
      .valueName("V")
      .defaultText("MAX_RANGE/100");
  cl.wholeNumber("--max-frames", a.max_frames, "only the first N scans (-1: all)").valueName("N");
  cl.flag("--tum", a.tum, "write TUM (\"t x y z qx qy qz qw\") instead of KITTI poses");
  cl.flag("--quiet", a.quiet, "no progress and no summary");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (!(a.min_range >= 0.0 && a.max_range > a.min_range)) {
    throw UsageError{"--min-range and --max-range must satisfy 0 <= min < max."};
  }
  if (!cl.given("--voxel")) a.voxel = a.max_range / 100.0;
  if (!(a.voxel > 0.0)) throw UsageError{"--voxel expects a positive size in metres."};
  if (cl.given("--max-frames") && a.max_frames < 1) {
    throw UsageError{"--max-frames expects a whole number of scans >= 1."};
  }
  return a;
}

Eigen::Isometry3d toIsometry(const Sophus::SE3d& pose) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = pose.rotationMatrix();
  out.translation() = pose.translation();
  return out;
}

int run(const Arguments& args) {
  // KISS-ICP's own range limits apply; the source keeps every finite point.
  std::unique_ptr<dlo::ScanSource> source;
  if (std::filesystem::is_directory(args.in)) {
    source = std::make_unique<dlo::KittiScanSource>(args.in);
  } else {
    source = std::make_unique<dlo::RawlogScanSource>(args.in);
  }
  kiss_icp::pipeline::KISSConfig config;
  config.max_range = args.max_range;
  config.min_range = args.min_range;
  config.voxel_size = args.voxel;
  config.deskew = false;
  config.max_num_threads = 1;
  kiss_icp::pipeline::KissICP odometry(config);

  dlo::metrics::Trajectory trajectory;
  dlo::ProgressBar bar(args.max_frames > 0 ? static_cast<size_t>(args.max_frames) : 0, "scans",
                       !args.quiet);
  dlo::TimedScan scan;
  std::vector<Eigen::Vector3d> frame;
  double seconds = 0.0;
  while ((args.max_frames < 0 || static_cast<long>(trajectory.size()) < args.max_frames) &&
         source->next(scan)) {
    frame.clear();
    frame.reserve(scan.points.size());
    for (const Eigen::Vector3f& p : scan.points) frame.push_back(p.cast<double>());
    const auto start = std::chrono::steady_clock::now();
    odometry.RegisterFrame(frame, {});
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Unix seconds, as dlo-slam's trajectory.tum and the ground truth have them (MRPT's clock
    // counts from 1601).
    trajectory.push_back(scan.timestampSeconds(), toIsometry(odometry.pose()));
    bar.update(trajectory.size());
  }
  bar.finish(trajectory.size());
  if (trajectory.empty() && source->stats().error.empty()) {
    throw dlo::InputError{"'" + args.in + "' holds no scans."};
  }
  if (args.tum) {
    dlo::metrics::writeTumTrajectory(args.out, trajectory);
  } else {
    dlo::metrics::writeKittiTrajectory(args.out, trajectory);
  }
  if (!args.quiet) {
    std::cout << "dlo-kiss-icp: " << trajectory.size() << " scans, "
              << (trajectory.empty() ? 0.0 : 1e3 * seconds / trajectory.size())
              << " ms per scan (RegisterFrame, mean); poses in '" << args.out << "'.\n";
  }
  if (!source->stats().error.empty()) {
    std::cerr << "dlo-kiss-icp: '" << args.in << "' breaks after " << trajectory.size()
              << " scans (their poses are written): " << source->stats().error << "\n";
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-kiss-icp", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
