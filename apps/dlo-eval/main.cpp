// dlo-eval: compares estimated trajectories with ground truth (ATE, RPE, KITTI drift) and draws
// the evaluation figures. Metrics and plotting live in libs/eval; this file parses the command
// line, decides how each estimate is paired with the ground truth, and writes the outputs.
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "dlo/app/app_main.h"
#include "dlo/app/program_options.h"
#include "dlo/eval/estimate_evaluation.h"
#include "dlo/eval/evaluation_figures.h"
#include "dlo/eval/evaluation_report.h"
#include "dlo/files/atomic_file.h"
#include "dlo/files/error.h"
#include "dlo/formats/png_file.h"
#include "dlo/metrics/trajectory_io.h"

namespace {

constexpr const char* kDescription =
    "Compares each estimated trajectory EST with the ground truth GT, writes metrics and figures "
    "into DIR (created if needed), each file atomically, and prints a table of the metrics.";

constexpr const char* kFooter = R"(Outputs in DIR:
  metrics.json         per estimate: matched poses, ATE (rmse, mean, median, max), RPE over 1
                       and 10 frames (translation m, rotation deg), KITTI drift (% and
                       deg/100 m over segments of 100..800 m) with the lengths used
  trajectories.png     top view (x-y) of the ground truth and every aligned estimate
  position_error.png   position error after alignment per ground-truth frame
  drift.png            KITTI translational drift per segment length

Files are TUM ("t x y z qx qy qz qw") or KITTI (12 numbers: 3x4 [R|t]), detected per file.
Pairing of estimate and ground-truth poses:
  TUM estimate     by timestamp: the nearest ground-truth pose within --max-dt seconds. A KITTI
                   ground truth then needs --gt-times (its sequence's times.txt).
  KITTI estimate   by index: estimate pose i with ground-truth pose i (KITTI files carry no
                   timestamps); it may have fewer poses than the ground truth, not more.
--alignment umeyama: SE(3) (rotation + translation, no scale) minimising the position error;
first: the estimate's first pose is put on the ground truth's. Used for the ATE and the
figures; RPE and KITTI drift are independent of it.

KITTI drift: segments start every 10 frames (as in the devkit); lengths longer than the ground
truth path are skipped; a path shorter than 100 m uses 10%, 20%, ..., 80% of its length.
Exit status: 0 on success, 1 for a bad input file (missing, malformed, fewer than 3 matched
poses), 2 for a command-line error; errors are one line on stderr starting with "dlo-eval: ".)";

using dlo::InputError;
using dlo::UsageError;
namespace metrics = dlo::metrics;

struct Arguments {
  std::string gt, gt_times, out;
  std::vector<std::string> estimates, labels;
  metrics::Alignment alignment = metrics::Alignment::kUmeyama;
  double max_dt = 0.02;
};

/// \return nullopt when --help was printed.
std::optional<Arguments> parseArguments(int argc, char** argv) {
  Arguments a;
  std::string alignment = "umeyama";
  dlo::ProgramOptions cl("dlo-eval", kDescription);
  cl.text("--gt", a.gt, "ground-truth trajectory").valueName("FILE").required();
  cl.repeatable("--est", a.estimates, "estimated trajectory; repeat to compare several")
      .valueName("FILE")
      .required();
  cl.repeatable("--label", a.labels,
                "name of the matching --est in tables and legends (default: the file name "
                "without extension); give none or one per --est")
      .valueName("NAME");
  cl.text("--out", a.out, "output folder").valueName("DIR").required();
  cl.text("--alignment", alignment, "umeyama or first (see below)").valueName("A");
  cl.number("--max-dt", a.max_dt, "largest timestamp difference of a pair, seconds").valueName("S");
  cl.text("--gt-times", a.gt_times, "one timestamp per line for a KITTI ground truth")
      .valueName("FILE");
  cl.footer(kFooter);
  if (!cl.parse(argc, argv)) return std::nullopt;
  if (alignment == "umeyama") {
    a.alignment = metrics::Alignment::kUmeyama;
  } else if (alignment == "first") {
    a.alignment = metrics::Alignment::kFirstPose;
  } else {
    throw UsageError{"--alignment expects umeyama or first, got '" + alignment + "'."};
  }
  if (!a.labels.empty() && a.labels.size() != a.estimates.size()) {
    throw UsageError{std::to_string(a.labels.size()) + " --label given for " +
                     std::to_string(a.estimates.size()) +
                     " --est: give one label per estimate, in the same order, or none."};
  }
  if (!(a.max_dt > 0.0)) throw UsageError{"--max-dt must be a positive number of seconds."};
  return a;
}

/// File names without extension; when two coincide (run1/trajectory.tum, run2/trajectory.tum)
/// the paths as given, which tell them apart.
std::vector<std::string> defaultLabels(const std::vector<std::string>& files) {
  std::vector<std::string> labels;
  std::map<std::string, int> uses;
  for (const std::string& f : files) {
    labels.push_back(std::filesystem::path(f).stem().string());
    ++uses[labels.back()];
  }
  for (size_t i = 0; i < files.size(); ++i) {
    if (uses[labels[i]] > 1) labels[i] = files[i];
  }
  return labels;
}

/// The readers name the file and line in their std::runtime_error; a user caused them.
metrics::Trajectory readTrajectoryFile(const std::string& role, const std::string& path,
                                       const std::vector<double>& kitti_times = {}) {
  try {
    return metrics::readTrajectory(path, kitti_times);
  } catch (const std::exception& e) {
    throw InputError("cannot read " + role + ": " + e.what());
  }
}

metrics::TrajectoryFormat formatOf(const std::string& role, const std::string& path) {
  try {
    return metrics::detectTrajectoryFormat(path);
  } catch (const std::exception& e) {
    throw InputError("cannot read " + role + ": " + e.what());
  }
}

int run(const Arguments& args) {
  const bool gt_is_kitti = formatOf("ground truth", args.gt) == metrics::TrajectoryFormat::kKitti;
  std::vector<double> gt_times;
  if (!args.gt_times.empty()) {
    if (!gt_is_kitti) {
      throw UsageError{"--gt-times is for a KITTI ground truth, but '" + args.gt +
                       "' is a TUM file with its own timestamps."};
    }
    try {
      gt_times = metrics::readTimestamps(args.gt_times);
    } catch (const std::exception& e) {
      throw InputError("cannot read --gt-times: " + std::string(e.what()));
    }
  }
  const metrics::Trajectory gt = readTrajectoryFile("ground truth", args.gt, gt_times);
  const bool gt_has_times = !gt_is_kitti || !gt_times.empty();

  dlo::eval::ComparisonSettings settings;
  settings.ground_truth_file = args.gt;
  settings.ground_truth_poses = gt.size();
  settings.max_dt = args.max_dt;
  settings.options.alignment = args.alignment;
  const std::vector<std::string> labels =
      args.labels.empty() ? defaultLabels(args.estimates) : args.labels;

  std::vector<dlo::eval::LabelledEvaluation> evaluations;
  for (size_t i = 0; i < args.estimates.size(); ++i) {
    const std::string& file = args.estimates[i];
    const bool est_is_kitti = formatOf("estimate", file) == metrics::TrajectoryFormat::kKitti;
    if (!est_is_kitti && !gt_has_times) {
      throw UsageError{"estimate '" + file + "' is stamped (TUM) but ground truth '" + args.gt +
                       "' is a KITTI file without timestamps: give --gt-times FILE."};
    }
    const metrics::Trajectory estimate = readTrajectoryFile("estimate", file);
    dlo::eval::LabelledEvaluation le;
    le.label = labels[i];
    le.file = file;
    le.poses = estimate.size();
    try {
      const dlo::eval::MatchedPair pair = est_is_kitti
                                              ? dlo::eval::matchByIndex(estimate, gt)
                                              : dlo::eval::matchByTime(estimate, gt, args.max_dt);
      le.evaluation = dlo::eval::evaluateEstimate(pair, settings.options);
    } catch (const std::invalid_argument& e) {
      throw InputError("estimate '" + file + "' against ground truth '" + args.gt +
                       "': " + e.what() + ".");
    }
    if (le.evaluation.ate.alignment != args.alignment) {
      std::cerr << "dlo-eval: warning: estimate '" << file
                << "' lies on a line, so its ATE uses the first-pose alignment.\n";
    }
    evaluations.push_back(std::move(le));
  }

  // Created only now: a bad input leaves no empty output folder behind.
  std::error_code ec;
  std::filesystem::create_directories(args.out, ec);
  if (!std::filesystem::is_directory(args.out)) {
    throw InputError("cannot create output folder '" + args.out + "'.");
  }
  const std::filesystem::path out(args.out);
  // Written atomically; an OutputError names the file (exit status 1 through runApp).
  const std::string json = dlo::eval::metricsJson(settings, evaluations);
  dlo::writeBytesAtomically((out / "metrics.json").string(),
                            std::vector<unsigned char>(json.begin(), json.end()));
  dlo::writePng(dlo::eval::trajectoriesFigure(gt, evaluations),
                (out / "trajectories.png").string());
  dlo::writePng(dlo::eval::positionErrorFigure(evaluations), (out / "position_error.png").string());
  dlo::writePng(dlo::eval::driftFigure(evaluations), (out / "drift.png").string());

  std::cout << dlo::eval::metricsTable(settings, evaluations);
  std::cout << "dlo-eval: metrics.json, trajectories.png, position_error.png, drift.png in '"
            << args.out << "'.\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return dlo::runApp("dlo-eval", [&] {
    const std::optional<Arguments> args = parseArguments(argc, argv);
    return args ? run(*args) : 0;
  });
}
