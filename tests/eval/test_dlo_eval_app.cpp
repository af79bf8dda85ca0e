// dlo-eval end to end: synthetic trajectories with known errors in, metrics.json, figures and
// exit statuses out.
#include <gtest/gtest.h>

#include "../json_file.h"
#include "../test_process.h"

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "dlo/eval/evaluation_figures.h"
#include "dlo/eval/plot2d.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo::eval {
namespace {

namespace fs = std::filesystem;
using metrics::Trajectory;

constexpr double kRadius = 20.0;  // a 126 m lap: the 100 m KITTI length fits once
constexpr size_t kPoses = 400;    // 10 Hz for 40 s
constexpr double kScaleError = 0.01;
const Eigen::Vector3d kOffset(0.5, -0.3, 0.2);

/// Counter-clockwise circle around the origin, heading along the motion.
Trajectory circle() {
  Trajectory t;
  for (size_t i = 0; i < kPoses; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i) / kPoses;
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::AngleAxisd(a + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    p.translation() = Eigen::Vector3d(kRadius * std::cos(a), kRadius * std::sin(a), 0.0);
    t.push_back(0.1 * static_cast<double>(i), p);
  }
  return t;
}

/// Every position scaled by 1 + kScaleError about the origin, then moved by kOffset.
Trajectory scaledAndOffset(const Trajectory& gt) {
  Trajectory t = gt;
  for (Eigen::Isometry3d& p : t.poses) {
    p.translation() = (1.0 + kScaleError) * p.translation() + kOffset;
  }
  return t;
}

/// 5 cm position noise per axis, stamps 4 ms late, every 7th pose missing.
Trajectory noisy(const Trajectory& gt) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.05);
  Trajectory t;
  for (size_t i = 0; i < gt.size(); ++i) {
    if (i % 7 == 0) continue;
    Eigen::Isometry3d p = gt.poses[i];
    p.translation() += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    t.push_back(gt.times[i] + 0.004, p);
  }
  return t;
}

struct CliRun {
  int status;
  std::string out, err;
};

std::string readFile(const fs::path& path) {
  return test::readFile(path.string());
}

/// The entry of metrics.json's "estimates" labelled `label`.
nlohmann::json estimateOf(const nlohmann::json& metrics, const std::string& label) {
  for (const nlohmann::json& e : metrics.at("estimates")) {
    if (e.at("label") == label) return e;
  }
  throw std::runtime_error("metrics.json has no estimate labelled " + label);
}

/// A number of metrics.json by its path of keys, e.g. {"ate", "rmse"}.
double number(const nlohmann::json& json, const std::vector<std::string>& keys) {
  const nlohmann::json* at = &json;
  for (const std::string& key : keys) at = &at->at(key);
  return at->get<double>();
}

class DloEval : public ::testing::Test {
 protected:
  void SetUp() override {
    // One folder per test: ctest runs tests in parallel.
    dir_ = fs::temp_directory_path() /
           (std::string("dlo_eval_") +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    gt_ = circle();
    metrics::writeTumTrajectory(path("gt.tum"), gt_);
    metrics::writeTumTrajectory(path("biased.tum"), scaledAndOffset(gt_));
    metrics::writeTumTrajectory(path("noisy.tum"), noisy(gt_));
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  CliRun dloEval(const std::string& args) const {
    const std::string cmd = std::string(DLO_EVAL_BINARY) + " " + args + " > " + path("out.txt") +
                            " 2> " + path("err.txt");
    const int raw = std::system(cmd.c_str());
    return CliRun{WEXITSTATUS(raw), readFile(path("out.txt")), readFile(path("err.txt"))};
  }

  fs::path dir_;
  Trajectory gt_;
};

TEST_F(DloEval, ReportsTheKnownErrorsOfAScaledAndANoisyEstimate) {
  const CliRun r =
      dloEval("--gt " + path("gt.tum") + " --est " + path("biased.tum") + " --est " +
              path("noisy.tum") + " --label biased --label noisy --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json json = test::readJsonFile(path("out/metrics.json"));
  EXPECT_EQ(json.at("settings").at("alignment_requested"), "umeyama-se3");
  const nlohmann::json biased = estimateOf(json, "biased");
  const nlohmann::json noisy = estimateOf(json, "noisy");

  EXPECT_EQ(biased.at("matched_poses"), kPoses);
  EXPECT_EQ(biased.at("alignment"), "umeyama-se3");
  // SE(3) alignment removes the offset and centres the scaled circle on the true one: every
  // position is then off by the scale error times the radius.
  for (const char* stat : {"rmse", "mean", "median", "max"}) {
    EXPECT_NEAR(number(biased, {"ate", stat}), kScaleError * kRadius, 1e-6) << stat;
  }
  // Frame-to-frame motion is stretched by the scale error, rotations are exact.
  const double chord1 = 2.0 * kRadius * std::sin(M_PI / kPoses);
  const double chord10 = 2.0 * kRadius * std::sin(10.0 * M_PI / kPoses);
  EXPECT_NEAR(number(biased, {"rpe", "1_frame", "translation_m", "max"}), kScaleError * chord1,
              1e-7);
  EXPECT_NEAR(number(biased, {"rpe", "10_frames", "translation_m", "rmse"}), kScaleError * chord10,
              1e-7);
  EXPECT_NEAR(number(biased, {"rpe", "1_frame", "rotation_deg", "max"}), 0.0, 1e-4);
  // KITTI: a 126 m path evaluates the 100 m length only; a pure scale error drifts by at most
  // the scale error (less: a 100 m arc has a shorter chord).
  EXPECT_EQ(biased.at("kitti").at("lengths"), nlohmann::json::array({100.0}));
  const double drift = number(biased, {"kitti", "translation_percent"});
  EXPECT_GT(drift, 0.1 * kScaleError * 100.0);
  EXPECT_LE(drift, kScaleError * 100.0 + 1e-9);
  EXPECT_NEAR(number(biased, {"kitti", "rotation_deg_per_100m"}), 0.0, 1e-4);

  // The noisy estimate lacks every 7th pose and is stamped 4 ms late: matched within 20 ms.
  EXPECT_EQ(noisy.at("poses"), kPoses - 58);
  EXPECT_EQ(noisy.at("matched_poses"), kPoses - 58);
  // 5 cm per axis: about 8.7 cm in 3D.
  EXPECT_NEAR(number(noisy, {"ate", "rmse"}), 0.05 * std::sqrt(3.0), 0.015);

  EXPECT_NE(r.out.find("biased"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("KITTI lengths for noisy: 100 m"), std::string::npos) << r.out;
}

TEST_F(DloEval, FirstPoseAlignmentLeavesAnOffsetThatStartsAfterTheFirstPose) {
  Trajectory jump = gt_;
  for (size_t i = 1; i < jump.size(); ++i) jump.poses[i].translation() += kOffset;
  metrics::writeTumTrajectory(path("jump.tum"), jump);
  const CliRun r = dloEval("--gt " + path("gt.tum") + " --est " + path("jump.tum") +
                           " --alignment first --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json estimates = test::readJsonFile(path("out/metrics.json")).at("estimates");
  ASSERT_EQ(estimates.size(), 1u);
  const nlohmann::json& jump_estimate = estimates[0];
  EXPECT_EQ(jump_estimate.at("alignment"), "first-pose");
  EXPECT_NEAR(number(jump_estimate, {"ate", "median"}), kOffset.norm(), 1e-6);
  EXPECT_NEAR(number(jump_estimate, {"ate", "max"}), kOffset.norm(), 1e-6);
  EXPECT_NEAR(number(jump_estimate, {"ate", "mean"}), kOffset.norm() * (kPoses - 1) / kPoses, 1e-6);
  // The default label is the file name without extension.
  EXPECT_EQ(jump_estimate.at("label"), "jump");
}

TEST_F(DloEval, KittiFilesArePairedByIndex) {
  metrics::writeKittiTrajectory(path("gt.kitti"), gt_);
  Trajectory first_half = scaledAndOffset(gt_);
  first_half.poses.resize(kPoses / 2);
  first_half.times.resize(kPoses / 2);
  metrics::writeKittiTrajectory(path("est.kitti"), first_half);
  const CliRun r =
      dloEval("--gt " + path("gt.kitti") + " --est " + path("est.kitti") + " --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json estimate =
      test::readJsonFile(path("out/metrics.json")).at("estimates").at(0);
  EXPECT_EQ(estimate.at("matched_poses"), kPoses / 2);
  EXPECT_EQ(estimate.at("matching"), "index");
  // Half a lap is 63 m: the KITTI lengths fall back to fractions of it.
  EXPECT_EQ(estimate.at("kitti").at("short_sequence"), true);
}

TEST_F(DloEval, FiguresHaveTheExpectedSizeContentAndLegendColours) {
  const CliRun r = dloEval("--gt " + path("gt.tum") + " --est " + path("biased.tum") + " --est " +
                           path("noisy.tum") + " --out " + path("out"));
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* name : {"trajectories.png", "position_error.png", "drift.png"}) {
    const cv::Mat image = cv::imread(path(std::string("out/") + name), cv::IMREAD_COLOR);
    ASSERT_FALSE(image.empty()) << name;
    EXPECT_EQ(image.size(), kFigureSize) << name;
    cv::Mat white;
    cv::inRange(image, cv::Scalar::all(255), cv::Scalar::all(255), white);
    EXPECT_GT(image.total() - cv::countNonZero(white), image.total() / 100) << name;
    for (size_t i = 0; i < 2; ++i) {
      const cv::Scalar c = seriesColour(i);
      cv::Mat mask;
      cv::inRange(image, c, c, mask);
      EXPECT_GT(cv::countNonZero(mask), 100) << name << " lacks the colour of estimate " << i;
    }
  }
}

TEST_F(DloEval, AMissingFileIsOneSentenceNamingIt) {
  const CliRun r =
      dloEval("--gt " + path("gt.tum") + " --est " + path("absent.tum") + " --out " + path("out"));
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err.rfind("dlo-eval: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("absent.tum"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(path("out")));
}

TEST_F(DloEval, AMalformedLineIsReportedWithFileAndLine) {
  std::ofstream(path("bad.tum")) << "0 0 0 0 0 0 0 1\n0.1 0 0 zero 0 0 0 1\n";
  const CliRun r =
      dloEval("--gt " + path("gt.tum") + " --est " + path("bad.tum") + " --out " + path("out"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("bad.tum' line 2"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST_F(DloEval, FewerThanThreeMatchedPosesIsAnInputError) {
  // Stamps 4 ms off cannot be matched within 1 ms.
  const CliRun r = dloEval("--gt " + path("gt.tum") + " --est " + path("noisy.tum") +
                           " --max-dt 0.001 --out " + path("out"));
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("at least 3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("noisy.tum"), std::string::npos) << r.err;
}

TEST_F(DloEval, CommandLineMistakesExitWithStatusTwo) {
  const std::string base = "--gt " + path("gt.tum") + " --out " + path("out");
  const CliRun labels =
      dloEval(base + " --est " + path("biased.tum") + " --est " + path("noisy.tum") + " --label a");
  EXPECT_EQ(labels.status, 2);
  EXPECT_NE(labels.err.find("1 --label given for 2 --est"), std::string::npos) << labels.err;
  EXPECT_EQ(dloEval(base).status, 2);  // no --est
  EXPECT_EQ(dloEval(base + " --est " + path("biased.tum") + " --alignment sim3").status, 2);
  EXPECT_EQ(dloEval(base + " --est " + path("biased.tum") + " --max-dt -1").status, 2);
  EXPECT_EQ(dloEval(base + " --est " + path("biased.tum") + " --frobnicate").status, 2);
  EXPECT_EQ(dloEval("--help").status, 0);
}

TEST_F(DloEval, AStampedEstimateAgainstAKittiGroundTruthNeedsGtTimes) {
  metrics::writeKittiTrajectory(path("gt.kitti"), gt_);
  const std::string args =
      "--gt " + path("gt.kitti") + " --est " + path("biased.tum") + " --out " + path("out");
  const CliRun without = dloEval(args);
  EXPECT_EQ(without.status, 2);
  EXPECT_NE(without.err.find("--gt-times"), std::string::npos) << without.err;
  metrics::writeTimestamps(path("times.txt"), gt_.times);
  const CliRun with = dloEval(args + " --gt-times " + path("times.txt"));
  ASSERT_EQ(with.status, 0) << with.err;
  EXPECT_EQ(test::readJsonFile(path("out/metrics.json")).at("estimates").at(0).at("matched_poses"),
            kPoses);
}

}  // namespace
}  // namespace dlo::eval
