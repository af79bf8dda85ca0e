// dlo-bench: DLO next to the classic registrators and external odometry programs (peers) on the
// same scans, with the same initial guess: timing, accuracy against ground truth and peak memory
// per method. The methods, peers and their evaluation live in libs/bench; this file parses the
// command line and writes the table.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/app/scan_input_options.h"
#include "dlo/bench/bench_table.h"
#include "dlo/bench/method_registry.h"
#include "dlo/bench/method_run.h"
#include "dlo/bench/peer_run.h"
#include "dlo/eval/evaluation_figures.h"
#include "dlo/files/atomic_file.h"
#include "dlo/files/error.h"
#include "dlo/formats/kitti_sequence.h"
#include "dlo/formats/png_file.h"
#include "dlo/metrics/trajectory_io.h"
#include "dlo/mrpt/kitti_conversion.h"
#include "dlo/mrpt/rawlog_scan_source.h"

namespace {

using dlo::UsageError;
namespace fs = std::filesystem;

constexpr const char* kDescription =
    "Runs every method on the same scans of IN, each in its own forked process (so that its peak "
    "memory is its own), and writes a table, trajectories and a figure into DIR (created if "
    "needed), each file atomically.";

constexpr const char* kFooter = R"(Outputs in DIR:
  table.md, table.csv      per method: preprocessing, frames, ms/frame (median, p95) of the
                           processing alone (points in the vehicle frame to pose; reading the
                           rawlog is not timed), frames/s, ATE RMSE (SE(3) Umeyama), KITTI
                           drift %, peak memory (MB)
  <method>.tum             each method's trajectory, relative to its first scan
  trajectories.png         top view of the ground truth and every method, aligned, with legend
  <peer>.poses, <peer>.log each peer's poses as it wrote them, and its stdout and stderr
The table is also printed. Without --gt the accuracy columns are n/a and the notes give where
each trajectory ends.

Methods (default: all of them):
  dlo-paper   the paper's frame-to-frame DLO (odometry.reference = previous, no loop closure)
  dlo         the full pipeline: local-map odometry, keyframe graph, loop closure (defaults)
  icp         MRPT CICP (3D, classic) frame to frame on cropped, voxel-filtered scans
  ndt, gicp   PCL's 3D-NDT and GICP, same preprocessing (only when built with PCL)
Frame-to-frame registrators start from a constant-velocity guess: for scan k,
pose_{k-1} * (pose_{k-2}^-1 pose_{k-1}); DLO's odometry predicts with constant velocity too.

Peers: --peer NAME=COMMAND (repeatable) adds an external odometry program. dlo-bench writes the
scans the methods get (vehicle frame, range limits and --max-frames applied) as a KITTI folder
(see dlo-rawlog2kitti; no poses.txt), runs COMMAND through /bin/sh with {kitti} replaced by that
folder and {out} by the file the peer must write: KITTI poses (one row-major 3x4 pose per scan,
in scan order) or TUM lines (stamped with times.txt's times), detected from the first line. The
peer's row is evaluated as the methods' are; its ms/frame is the wall time of the whole process
divided by the scans, so it includes the peer's start-up and its reading of the files. A peer
that fails or writes a wrong number of poses gets a failed row; the others are kept. The KITTI
folder is removed at the end. Example, with a KISS-ICP driver that you built from its source:
  dlo-bench --input drive.rawlog --gt gt.tum --out bench \
            --peer "KISS-ICP=/path/to/kiss_driver {kitti} {out}"
--kiss-icp is that peer with dlo-kiss-icp, when this build has it (configured with
-DDLO_KISS_ICP_SOURCE=...; scripts/build_kiss_icp_peer.sh).

Exit status: 0 on success, 1 for a bad input file or a method or peer that failed (the table is
still written), 2 for a command-line error; errors are one line on stderr starting with
"dlo-bench: ".)";

struct Arguments {
  std::string input, gt, out;
  std::vector<const dlo::bench::MethodSpec*> methods;
  std::vector<dlo::bench::PeerSpec> peers;
  long max_frames = -1;
  long max_frames_slow = 100;
  long repeat = 1;
  dlo::ScanInputOptions scans;  // the ranges; --max-frames is the benchmark's own
  bool quiet = false;
};

/// `text`, the value of `option`, as a whole number (of `what`) >= 1.
long toCount(const std::string& option, const std::string& text,
             const std::string& what = "frames") {
  double v = 0.0;
  try {
    size_t used = 0;
    v = std::stod(text, &used);
    if (used != text.size()) throw std::invalid_argument(text);
  } catch (const std::exception&) {
    throw UsageError{option + " expects a number, got '" + text + "'."};
  }
  if (!(v >= 1.0) || v != std::floor(v)) {
    throw UsageError{option + " expects a whole number of " + what + " >= 1, got '" + text + "'."};
  }
  return static_cast<long>(v);
}

std::vector<const dlo::bench::MethodSpec*> parseMethods(const std::string& list) {
  std::vector<const dlo::bench::MethodSpec*> methods;
  std::istringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    if (name.empty()) continue;
    const dlo::bench::MethodSpec* m = dlo::bench::findMethod(name);
    if (!m) {
      throw UsageError{"unknown method '" + name + "' in --methods (this build has " +
                       dlo::bench::availableMethodNames() + ")."};
    }
    if (std::find(methods.begin(), methods.end(), m) == methods.end()) methods.push_back(m);
  }
  if (methods.empty()) throw UsageError{"--methods names no method."};
  return methods;
}

/// --kiss-icp: the peer spec of this build's dlo-kiss-icp.
std::string kissIcpPeer() {
#ifdef DLO_KISS_ICP_DRIVER
  return std::string("KISS-ICP='") + DLO_KISS_ICP_DRIVER + "' --quiet {kitti} {out}";
#else
  throw UsageError{
      "--kiss-icp needs a build with KISS-ICP (cmake -DDLO_KISS_ICP_SOURCE=..., see "
      "scripts/build_kiss_icp_peer.sh); or give its driver with --peer."};
#endif
}

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  // The counts are read here, not by the parser, for their messages ("of runs >= 1").
  std::string methods, max_frames, max_frames_slow, repeat;
  std::vector<std::string> peers;
  bool kiss_icp = false;
  dlo::ProgramOptions cl("dlo-bench", kDescription);
  cl.text("--input", a.input, "the scans: an MRPT rawlog").valueName("IN.rawlog").required();
  cl.text("--gt", a.gt, "ground truth (TUM) for the accuracy columns").valueName("GT.tum");
  cl.text("--out", a.out, "output folder").valueName("DIR").required();
  cl.text("--methods", methods, "comma-separated method names (default: all; see Methods)")
      .valueName("LIST");
  cl.repeatable("--peer", peers,
                "an external odometry program (see Peers below); repeatable. NAME holds letters, "
                "digits and . _ + -; COMMAND must contain {out}")
      .valueName("NAME=COMMAND");
  cl.flag("--kiss-icp", kiss_icp,
          "KISS-ICP as a peer named KISS-ICP, through this build's dlo-kiss-icp");
  cl.text("--max-frames", max_frames, "at most N scans per method").valueName("N");
  cl.text("--max-frames-slow", max_frames_slow,
          "at most N scans for the slow methods (icp, ndt, gicp)")
      .valueName("N")
      .defaultText("100");
  dlo::declareScanInputOptions(cl, a.scans, dlo::kScanRange);
  cl.text("--repeat", repeat,
          "run every method N times, in N rounds that each run every method once, so that all "
          "of them are timed under the machine's load of the whole benchmark; a scan's time is "
          "the median of its N times. On a shared machine this steadies the ratios between "
          "methods")
      .valueName("N")
      .defaultText("1");
  cl.flag("--quiet", a.quiet, "no progress");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (cl.given("--max-frames")) a.max_frames = toCount("--max-frames", max_frames);
  if (cl.given("--max-frames-slow")) {
    a.max_frames_slow = toCount("--max-frames-slow", max_frames_slow);
  }
  if (cl.given("--repeat")) a.repeat = toCount("--repeat", repeat, "runs");
  dlo::checkScanInputOptions(a.scans);
  if (methods.empty()) {
    for (const auto& m : dlo::bench::availableMethods()) a.methods.push_back(&m);
  } else {
    a.methods = parseMethods(methods);
  }
  if (kiss_icp) peers.push_back(kissIcpPeer());
  for (const std::string& text : peers) {
    try {
      a.peers.push_back(dlo::bench::parsePeerSpec(text));
    } catch (const std::invalid_argument& e) {
      throw UsageError{e.what()};
    }
    const std::string& name = a.peers.back().name;
    const bool twice = std::count_if(a.peers.begin(), a.peers.end(),
                                     [&](const auto& p) { return p.name == name; }) > 1;
    if (twice || dlo::bench::findMethod(name)) {
      throw UsageError{"--peer name '" + name + "' is used twice or is a method's name."};
    }
  }
  return a;
}

std::string commandLine(int argc, char** argv) {
  std::string text = "dlo-bench";
  for (int i = 1; i < argc; ++i) text += std::string(" ") + argv[i];
  return text;
}

/// "2 x AMD EPYC" from /proc/cpuinfo, for the table's provenance line.
std::string machine() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  int cpus = 0;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    ++cpus;
    model = line.substr(line.find(':') + 2);
  }
  return std::to_string(cpus) + " x " + model;
}

/// Top view of the ground truth and every estimate after its ATE alignment (dlo::eval's figure,
/// as dlo-eval draws it). Estimates with fewer than 3 poses matched are left out.
cv::Mat trajectoriesFigure(
    const dlo::metrics::Trajectory& ground_truth,
    const std::vector<std::pair<std::string, dlo::metrics::Trajectory>>& estimates) {
  std::vector<dlo::eval::LabelledEvaluation> evaluations;
  for (const auto& [name, trajectory] : estimates) {
    const dlo::eval::MatchedPair pair = dlo::eval::matchByTime(trajectory, ground_truth, 0.005);
    if (pair.estimate.size() < dlo::eval::kMinMatchedPoses) continue;
    dlo::eval::LabelledEvaluation e;
    e.label = name;
    e.poses = trajectory.size();
    e.evaluation = dlo::eval::evaluateEstimate(pair, dlo::eval::EvaluationOptions());
    evaluations.push_back(std::move(e));
  }
  return dlo::eval::trajectoriesFigure(ground_truth, evaluations);
}

void writeText(const fs::path& path, const std::string& text) {
  dlo::writeBytesAtomically(path.string(), std::vector<unsigned char>(text.begin(), text.end()));
}

/// Whether --max-frames-slow stopped a slow method before the others: a slow method was run and
/// some method processed more scans than the limit.
bool slowLimitCut(const Arguments& args, const std::vector<dlo::bench::MethodRun>& runs) {
  const bool any_slow =
      std::any_of(args.methods.begin(), args.methods.end(), [](const auto* m) { return m->slow; });
  return any_slow && std::any_of(runs.begin(), runs.end(), [&](const auto& run) {
           return run.ms.size() > static_cast<size_t>(args.max_frames_slow);
         });
}

/// The notes under the table; `slow_cut` is slowLimitCut(), `have_gt` whether --gt was given.
std::string notes(const Arguments& args, const std::vector<dlo::bench::MethodRow>& rows,
                  const std::vector<dlo::bench::MethodRun>& runs, bool slow_cut, bool have_gt) {
  double baseline = 0.0;
  for (const auto& run : runs) baseline = std::max(baseline, run.baseline_memory_mb);
  std::ostringstream o;
  o << "\n* ms/frame: wall time of one method's processing of a scan (points in the vehicle "
       "frame to pose, including its own deskewing, filtering and map upkeep); reading and "
       "decoding the rawlog are not timed. frames/s = frames / total processing time. Methods "
       "run one after another, single-threaded.\n";
  for (const dlo::bench::PeerSpec& peer : args.peers) {
    o << "* " << peer.name << " (peer): `" << peer.command
      << "` on the same scans written as a KITTI folder; ms/frame is the wall time of the whole "
         "process / scans (including its start-up and reading of the files), threads as the "
         "program uses them.\n";
  }
  if (have_gt) {
    o << "* ATE: RMSE of positions after SE(3) Umeyama alignment to the ground truth "
         "(dlo::metrics), poses matched by timestamp within 5 ms. drift: KITTI translational "
         "drift averaged over segments of";
    for (const auto& r : rows) o << " " << r.method << ": " << r.drift_lengths << ";";
    o << " segment lengths are fractions of the path when it is shorter than 100 m.\n";
  } else {
    o << "* No ground truth (--gt): accuracy not evaluated. Where each trajectory ends, in its "
         "first scan's frame (x forward):";
    for (const auto& run : runs) {
      if (run.trajectory.empty()) continue;
      const Eigen::Vector3d end = run.trajectory.poses.back().translation();
      char text[160];
      std::snprintf(text, sizeof text, " %s (%.2f, %.2f, %.2f) m;", run.method.c_str(), end.x(),
                    end.y(), end.z());
      o << text;
    }
    o << "\n";
  }
  o << "* peak memory: peak resident set (VmHWM) of a child process forked for the method alone "
       "(high-water mark reset after the fork), which reads the rawlog itself; it includes the "
       "program's baseline of about "
    << static_cast<int>(std::lround(baseline)) << " MB (libraries, scan reader)";
  if (!args.peers.empty()) o << "; not measured for the peers";
  o << ".\n";
  o << "* Initial guess: the frame-to-frame registrators (icp, ndt, gicp) start scan k at "
       "pose_{k-1} * (pose_{k-2}^-1 pose_{k-1}) and get the scans as measured (not deskewed); "
       "dlo-paper and dlo use LidarOdometry's own constant-velocity prediction (planar, over the "
       "last two intervals) and deskew with it.\n";
  if (args.repeat > 1) {
    o << "* --repeat " << args.repeat << ": every method ran " << args.repeat
      << " times, in rounds that each ran every method once; a scan's time is the median of its "
      << args.repeat << " times, and ms/frame, p95 and frames/s are taken over those.";
    bool agree = true;
    for (const auto& run : runs) {
      if (run.error.empty() && run.pass_disagreement_m > 0.0) {
        agree = false;
        o << " " << run.method << "'s passes placed a scan up to " << run.pass_disagreement_m
          << " m apart (the first pass's trajectory is evaluated).";
      }
    }
    if (agree) o << " Every method gave the same trajectory in every pass.";
    o << "\n";
  }
  // The slow methods' limit is stated where it cut them short of the others, not when every
  // method ran the same scans.
  if (slow_cut || args.max_frames > 0) {
    if (slow_cut) {
      o << "* Slow methods are limited to the first " << args.max_frames_slow
        << " scans (--max-frames-slow)";
      if (args.max_frames > 0) o << ", all methods to " << args.max_frames << " (--max-frames)";
    } else {
      o << "* All methods are limited to the first " << args.max_frames << " scans (--max-frames)";
    }
    o << ".\n";
  }
  for (const auto& r : rows) {
    if (!r.error.empty()) o << "* " << r.method << ": " << r.error << "\n";
  }
  return o.str();
}

int run(const Arguments& args, const std::string& command) {
  dlo::metrics::Trajectory ground_truth;
  try {
    if (!args.gt.empty()) ground_truth = dlo::metrics::readTrajectory(args.gt);
  } catch (const std::exception& e) {
    throw dlo::InputError("cannot read ground truth '" + args.gt + "': " + e.what());
  }
  if (fs::is_directory(args.input)) {
    throw dlo::InputError("input '" + args.input + "' is a folder, expected an MRPT rawlog.");
  }
  dlo::ScanSourceOptions options;
  options.min_range = args.scans.min_range;
  options.max_range = args.scans.max_range;
  { dlo::RawlogScanSource check(args.input, options); }  // names the file if it is not a rawlog
  std::error_code ec;
  fs::create_directories(args.out, ec);
  if (!fs::is_directory(args.out)) {
    throw dlo::InputError("cannot create output folder '" + args.out + "'.");
  }

  // The peers' input: the scans the methods get, written once for all peers and rounds.
  const fs::path kitti = fs::path(args.out) / "peer-scans";
  std::vector<double> scan_times;
  if (!args.peers.empty()) {
    if (!args.quiet) std::cerr << "dlo-bench: writing the scans for the peers to " << kitti << "\n";
    fs::remove_all(kitti, ec);
    dlo::convertRawlogToKitti(args.input, kitti.string(), "", options, args.max_frames);
    scan_times = dlo::readKittiSequence(kitti.string()).times;
  }

  std::vector<dlo::bench::MethodRun> runs;
  std::vector<dlo::bench::MethodRow> rows;
  std::vector<std::pair<std::string, dlo::metrics::Trajectory>> trajectories;
  bool failed = false;
  // Round after round, every method once per round: each is timed over the whole benchmark's
  // span of the machine's load, not in a window of its own.
  std::vector<std::vector<dlo::bench::MethodRun>> passes(args.methods.size());
  std::vector<std::vector<dlo::bench::MethodRun>> peer_passes(args.peers.size());
  // Scans per method (negative: all): --max-frames, and --max-frames-slow for the slow ones.
  std::vector<long> limits;
  for (const dlo::bench::MethodSpec* spec : args.methods) {
    const long limit = args.max_frames;
    limits.push_back(!spec->slow ? limit
                     : limit < 0 ? args.max_frames_slow
                                 : std::min(limit, args.max_frames_slow));
  }
  for (long round = 1; round <= args.repeat; ++round) {
    for (size_t m = 0; m < args.methods.size(); ++m) {
      const dlo::bench::MethodSpec* spec = args.methods[m];
      if (!args.quiet) {
        std::cerr << "dlo-bench: " << spec->name;
        if (args.repeat > 1) std::cerr << " (round " << round << " of " << args.repeat << ")";
        std::cerr << "\n";
      }
      passes[m].push_back(
          dlo::bench::runMethodIsolated(*spec, args.input, options, limits[m], !args.quiet));
    }
    for (size_t p = 0; p < args.peers.size(); ++p) {
      const dlo::bench::PeerSpec& peer = args.peers[p];
      if (!args.quiet) std::cerr << "dlo-bench: " << peer.name << " (peer)\n";
      const fs::path out = fs::path(args.out) / peer.name;
      peer_passes[p].push_back(dlo::bench::runPeer(peer, kitti.string(), scan_times,
                                                   out.string() + ".poses", out.string() + ".log"));
    }
  }
  if (!args.peers.empty()) fs::remove_all(kitti, ec);
  for (size_t m = 0; m < args.methods.size(); ++m) {
    const dlo::bench::MethodSpec* spec = args.methods[m];
    runs.push_back(dlo::bench::combinePasses(passes[m]));
    const dlo::bench::MethodRun& r = runs.back();
    if (!r.input_warning.empty()) std::cerr << "dlo-bench: warning: " << r.input_warning << "\n";
    if (!r.error.empty() || r.trajectory.empty()) {
      failed = true;
      std::cerr << "dlo-bench: " << spec->name
                << " failed: " << (r.error.empty() ? "no scan processed." : r.error) << "\n";
    }
    rows.push_back(dlo::bench::evaluateRun(r, spec->preprocessing, ground_truth));
    if (!r.trajectory.empty()) {
      dlo::metrics::writeTumTrajectory((fs::path(args.out) / (spec->name + ".tum")).string(),
                                       r.trajectory);
      trajectories.emplace_back(spec->name, r.trajectory);
    }
  }
  for (size_t p = 0; p < args.peers.size(); ++p) {
    const dlo::bench::PeerSpec& peer = args.peers[p];
    runs.push_back(dlo::bench::combinePasses(peer_passes[p]));
    const dlo::bench::MethodRun& r = runs.back();
    if (!r.error.empty()) {
      failed = true;
      std::cerr << "dlo-bench: peer " << peer.name << " failed: " << r.error << "\n";
    }
    rows.push_back(dlo::bench::evaluateRun(r, "external program (ms/frame: whole process / scans)",
                                           ground_truth));
    if (!r.trajectory.empty()) {
      dlo::metrics::writeTumTrajectory((fs::path(args.out) / (peer.name + ".tum")).string(),
                                       r.trajectory);
      trajectories.emplace_back(peer.name, r.trajectory);
    }
  }

  // The slow methods see only the start of the sequence: the same span for the others, so that
  // accuracy is compared on equal ground.
  const bool slow_cut = slowLimitCut(args, runs);
  std::ostringstream md;
  md << "Command: `" << command << "`  \nMachine: " << machine() << "\n\n"
     << dlo::bench::tableMarkdown(rows) << notes(args, rows, runs, slow_cut, !ground_truth.empty());
  std::vector<dlo::bench::MethodRow> first;
  for (size_t i = 0; i < runs.size() && slow_cut; ++i) {
    if (runs[i].ms.size() > static_cast<size_t>(args.max_frames_slow)) {
      first.push_back(dlo::bench::evaluateRun(runs[i], rows[i].preprocessing, ground_truth,
                                              args.max_frames_slow));
    }
  }
  if (!first.empty()) {
    md << "\nThe same runs over their first " << args.max_frames_slow
       << " scans only (the span of the slow methods; timing and accuracy of that span, memory "
          "of the whole run):\n\n"
       << dlo::bench::tableMarkdown(first);
  }
  writeText(fs::path(args.out) / "table.md", md.str());
  writeText(fs::path(args.out) / "table.csv", dlo::bench::tableCsv(rows));
  if (!ground_truth.empty()) {
    dlo::writePng(trajectoriesFigure(ground_truth, trajectories),
                  (fs::path(args.out) / "trajectories.png").string());
  }
  std::cout << md.str();
  return failed ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-bench", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args, commandLine(argc, argv)) : 0;
  });
}
