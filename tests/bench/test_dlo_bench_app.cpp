// dlo-bench end to end: the built binary on a short simulated HDL-64 drive, every method, fake
// external peers (shell one-liners), and the command-line and input errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include "../test_process.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "dlo/bench/method_registry.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo::bench {
namespace {

namespace fs = std::filesystem;

std::string readFile(const fs::path& path) {
  return test::readFile(path.string());
}

/// Splits one CSV line; quoted cells may hold commas.
std::vector<std::string> csvCells(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (c == '"') {
      if (quoted && i + 1 < line.size() && line[i + 1] == '"') {
        cells.back() += '"';
        ++i;
      } else {
        quoted = !quoted;
      }
    } else if (c == ',' && !quoted) {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

/// A 30-sweep simulated drive and one dlo-bench run over it, shared by the tests of this file.
class DloBenchApp : public ::testing::Test {
 protected:
  static constexpr int kFrames = 30;
  static constexpr int kSlowFrames = 5;

  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("dlo_bench_app_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const std::string sim = std::string(DLO_SIMULATE_BINARY) + " --out " + dir_->string() +
                            " --frames " + std::to_string(kFrames) +
                            " --sensor HDL64 --seed 1 --quiet";
    ASSERT_EQ(std::system(sim.c_str()), 0) << sim;
    status_ = bench("--out " + (*dir_ / "out").string() + " --max-frames-slow " +
                    std::to_string(kSlowFrames));
  }
  static void TearDownTestSuite() {
    if (!std::getenv("DLO_KEEP_TEST_OUTPUT")) fs::remove_all(*dir_);
    delete dir_;
  }

  /// Runs dlo-bench on the simulated drive with `arguments`; stderr goes to stderr_path().
  /// \return its exit status.
  static int bench(const std::string& arguments, const std::string& input = "") {
    const std::string cmd = std::string(DLO_BENCH_BINARY) + " --input " +
                            (input.empty() ? (*dir_ / "sequence.rawlog").string() : input) +
                            " --gt " + (*dir_ / "groundtruth.tum").string() + " --quiet " +
                            arguments + " > " + (*dir_ / "stdout.txt").string() + " 2> " +
                            stderrPath();
    const int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  static std::string stderrPath() { return (*dir_ / "stderr.txt").string(); }
  static fs::path out() { return *dir_ / "out"; }

  static fs::path* dir_;
  static int status_;
};
fs::path* DloBenchApp::dir_ = nullptr;
int DloBenchApp::status_ = -1;

TEST_F(DloBenchApp, TableHasOnePlausibleRowPerMethod) {
  ASSERT_EQ(status_, 0) << readFile(stderrPath());
  std::istringstream csv(readFile(out() / "table.csv"));
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line,
            "method,preprocessing,frames,ms_median,ms_p95,frames_per_s,ate_m,drift_percent,"
            "peak_memory_mb");
  std::map<std::string, std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = csvCells(line);
    ASSERT_EQ(cells.size(), 9u) << line;
    EXPECT_TRUE(rows.emplace(cells[0], cells).second) << "duplicate row " << cells[0];
  }
  ASSERT_EQ(rows.size(), availableMethods().size());
  for (const MethodSpec& m : availableMethods()) {
    SCOPED_TRACE(m.name);
    ASSERT_TRUE(rows.count(m.name));
    const std::vector<std::string>& r = rows[m.name];
    EXPECT_FALSE(r[1].empty());
    EXPECT_EQ(std::stoi(r[2]), m.slow ? kSlowFrames : kFrames);
    const double median = std::stod(r[3]), p95 = std::stod(r[4]), fps = std::stod(r[5]);
    EXPECT_GT(median, 0.0);
    EXPECT_GE(p95, median);
    EXPECT_GT(fps, 0.0);
    const double ate = std::stod(r[6]);
    EXPECT_TRUE(std::isfinite(ate));
    // A few sweeps of a simulated straight: every method stays within a metre, except PCL's
    // NDT (built only with libpcl-dev), whose 2 m cells slide along the street: 1.28 m here.
    EXPECT_LT(ate, m.name == "ndt" ? 2.0 : 1.0);
    EXPECT_TRUE(std::isfinite(std::stod(r[7])));
    const double memory = std::stod(r[8]);
    EXPECT_GT(memory, 5.0);
    EXPECT_LT(memory, 4096.0);
  }
  // DLO itself should do what the README measures: centimetres, not decimetres, on this drive.
  EXPECT_LT(std::stod(rows["dlo"][6]), 0.2);
}

TEST_F(DloBenchApp, WritesEveryTrajectoryTheTableAndThePlot) {
  ASSERT_EQ(status_, 0) << readFile(stderrPath());
  for (const MethodSpec& m : availableMethods()) {
    const metrics::Trajectory t = metrics::readTumTrajectory((out() / (m.name + ".tum")).string());
    EXPECT_EQ(t.size(), static_cast<size_t>(m.slow ? kSlowFrames : kFrames)) << m.name;
    EXPECT_TRUE(t.poses.front().isApprox(Eigen::Isometry3d::Identity(), 1e-9)) << m.name;
  }
  const std::string md = readFile(out() / "table.md");
  EXPECT_NE(md.find("| method | preprocessing | frames | ms/frame median | p95 | frames/s | "
                    "ATE m | drift % | peak memory MB |"),
            std::string::npos);
  EXPECT_NE(md.find("Command: `dlo-bench "), std::string::npos);
  EXPECT_NE(readFile(*dir_ / "stdout.txt").find("| dlo-paper |"), std::string::npos);
  ASSERT_TRUE(fs::exists(out() / "trajectories.png"));
  EXPECT_GT(fs::file_size(out() / "trajectories.png"), 10000u);
  for (const auto& entry : fs::directory_iterator(out())) {
    EXPECT_NE(entry.path().extension(), ".tmp") << "temporary file left: " << entry.path();
  }
}

TEST_F(DloBenchApp, MethodsAndFrameLimitsAreHonoured) {
  const fs::path dir = *dir_ / "subset";
  ASSERT_EQ(bench("--out " + dir.string() + " --methods icp,dlo-paper --max-frames 4"), 0)
      << readFile(stderrPath());
  const std::string csv = readFile(dir / "table.csv");
  EXPECT_NE(csv.find("\nicp,"), std::string::npos);
  EXPECT_NE(csv.find("\ndlo-paper,"), std::string::npos);
  EXPECT_EQ(csv.find("\ndlo,"), std::string::npos);
  EXPECT_EQ(metrics::readTumTrajectory((dir / "dlo-paper.tum").string()).size(), 4u);
  EXPECT_EQ(metrics::readTumTrajectory((dir / "icp.tum").string()).size(), 4u);
  EXPECT_FALSE(fs::exists(dir / "dlo.tum"));
  // Every method ran the same 4 scans: only --max-frames limited them, and there is no table of
  // the slow methods' span.
  const std::string md = readFile(dir / "table.md");
  EXPECT_NE(md.find("* All methods are limited to the first 4 scans (--max-frames)."),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("--max-frames-slow"), std::string::npos) << md;
  EXPECT_EQ(md.find("The same runs over their first"), std::string::npos) << md;
  // The shared run cut the slow methods at kSlowFrames scans of kFrames: stated, and the
  // others' first kSlowFrames scans tabled.
  const std::string shared = readFile(out() / "table.md");
  EXPECT_NE(shared.find("* Slow methods are limited to the first " + std::to_string(kSlowFrames) +
                        " scans (--max-frames-slow)."),
            std::string::npos)
      << shared;
  EXPECT_NE(shared.find("The same runs over their first " + std::to_string(kSlowFrames)),
            std::string::npos)
      << shared;
}

TEST_F(DloBenchApp, RepeatTimesEveryMethodInRoundsAndChecksThePassesAgree) {
  const fs::path dir = *dir_ / "repeat";
  ASSERT_EQ(bench("--out " + dir.string() + " --methods dlo-paper,icp --max-frames 4 --repeat 3"),
            0)
      << readFile(stderrPath());
  const std::string md = readFile(dir / "table.md");
  EXPECT_NE(md.find("--repeat 3: every method ran 3 times, in rounds that each ran every method "
                    "once; a scan's time is the median of its 3 times"),
            std::string::npos)
      << md;
  // Both methods are deterministic: a difference between passes would be a bug.
  EXPECT_NE(md.find("Every method gave the same trajectory in every pass."), std::string::npos)
      << md;
  EXPECT_EQ(metrics::readTumTrajectory((dir / "dlo-paper.tum").string()).size(), 4u);
  EXPECT_EQ(metrics::readTumTrajectory((dir / "icp.tum").string()).size(), 4u);
  EXPECT_EQ(readFile(out() / "table.md").find("--repeat"), std::string::npos)
      << "one pass by default";
  EXPECT_EQ(bench("--out " + dir.string() + " --repeat 0"), 2);
  EXPECT_NE(readFile(stderrPath()).find("--repeat expects a whole number of runs >= 1, got '0'"),
            std::string::npos)
      << readFile(stderrPath());
}

/// CSV rows of `table` by method name.
std::map<std::string, std::vector<std::string>> csvRows(const std::string& table) {
  std::istringstream csv(table);
  std::string line;
  std::getline(csv, line);
  std::map<std::string, std::vector<std::string>> rows;
  while (std::getline(csv, line)) {
    const std::vector<std::string> cells = csvCells(line);
    rows[cells[0]] = cells;
  }
  return rows;
}

TEST_F(DloBenchApp, PeersRunOnTheSameScansAndFailingPeersKeepTheOtherRows) {
  const fs::path dir = *dir_ / "peers";
  const std::string gt = (*dir_ / "groundtruth.tum").string();
  // "truth" writes the ground truth of the 6 scans (TUM), "still" identity poses (KITTI, one
  // per line of {kitti}/times.txt), "broken" exits with status 3, "short" writes every pose of
  // the 30-scan drive for the 6 scans it was given.
  const std::string peers =
      " --peer " + test::shellQuote("truth=grep -v '^#' " + gt + " | head -n 6 > {out}") +
      " --peer " +
      test::shellQuote(
          "still=awk '{print \"1 0 0 0 0 1 0 0 0 0 1 0\"}' {kitti}/times.txt > {out}") +
      " --peer " + test::shellQuote("broken=echo no luck; exit 3; cat {out}") + " --peer " +
      test::shellQuote("short=cp " + gt + " {out}");
  EXPECT_EQ(bench("--out " + dir.string() + " --methods dlo-paper --max-frames 6" + peers), 1)
      << "a failed peer is a failed run";
  const std::string err = readFile(stderrPath());
  EXPECT_NE(err.find("dlo-bench: peer broken failed: the command exited with status 3"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("dlo-bench: peer short failed: it wrote 30 poses"), std::string::npos) << err;
  EXPECT_NE(err.find("for 6 scans; expected one per scan."), std::string::npos) << err;
  EXPECT_NE(readFile(dir / "broken.log").find("no luck"), std::string::npos);

  auto rows = csvRows(readFile(dir / "table.csv"));
  ASSERT_EQ(rows.size(), 5u) << readFile(dir / "table.csv");
  for (const std::string name : {"dlo-paper", "truth", "still"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(rows.count(name));
    EXPECT_EQ(rows[name][2], "6");
    EXPECT_GT(std::stod(rows[name][3]), 0.0);
    EXPECT_EQ(metrics::readTumTrajectory((dir / (name + ".tum")).string()).size(), 6u);
  }
  // Evaluated as the methods are: the ground truth itself has no error, standing still does.
  EXPECT_LT(std::stod(rows["truth"][6]), 1e-6);
  EXPECT_GT(std::stod(rows["still"][6]), 0.5);
  EXPECT_LT(std::stod(rows["dlo-paper"][6]), 0.5 * std::stod(rows["still"][6]));
  EXPECT_GT(std::stod(rows["still"][7]), 90.0) << "no motion: about 100 % drift";
  for (const std::string name : {"broken", "short"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(rows.count(name));
    EXPECT_EQ(rows[name][6], "") << "no accuracy for a failed peer";
    EXPECT_FALSE(fs::exists(dir / (name + ".tum")));
  }
  const std::string md = readFile(dir / "table.md");
  EXPECT_NE(md.find("| still | external program (ms/frame: whole process / scans) | 6 |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("* broken: the command exited with status 3"), std::string::npos) << md;
  EXPECT_FALSE(fs::exists(dir / "peer-scans")) << "the peers' KITTI folder is removed";
}

TEST_F(DloBenchApp, WithoutGroundTruthTheNotesGiveWhereEachTrajectoryEnds) {
  const fs::path dir = *dir_ / "nogt";
  const std::string cmd = std::string(DLO_BENCH_BINARY) + " --input " +
                          (*dir_ / "sequence.rawlog").string() + " --quiet --out " + dir.string() +
                          " --methods dlo-paper --max-frames 5 > /dev/null 2> " + stderrPath();
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readFile(stderrPath());
  const std::string md = readFile(dir / "table.md");
  EXPECT_NE(md.find("* No ground truth (--gt): accuracy not evaluated."), std::string::npos) << md;
  EXPECT_NE(md.find(" dlo-paper ("), std::string::npos) << md;
  EXPECT_EQ(csvRows(readFile(dir / "table.csv"))["dlo-paper"][6], "");
}

TEST_F(DloBenchApp, BadPeersAreCommandLineErrorsNamingThem) {
  const std::string out = " --out " + (*dir_ / "badpeer").string() + " --methods dlo-paper";
  EXPECT_EQ(bench(out + " --peer just-a-name"), 2);
  EXPECT_NE(readFile(stderrPath()).find("--peer expects NAME=COMMAND, got 'just-a-name'"),
            std::string::npos)
      << readFile(stderrPath());
  EXPECT_EQ(bench(out + " --peer " + test::shellQuote("p=echo hello")), 2);
  EXPECT_NE(readFile(stderrPath()).find("must contain {out}"), std::string::npos);
  EXPECT_EQ(bench(out + " --peer " + test::shellQuote("dlo=cp x {out}")), 2);
  EXPECT_NE(readFile(stderrPath()).find("'dlo'"), std::string::npos);
  EXPECT_EQ(bench(out + " --peer " + test::shellQuote("a/b=cp x {out}")), 2);
  EXPECT_FALSE(fs::exists(*dir_ / "badpeer"));
}

TEST_F(DloBenchApp, UnknownMethodIsACommandLineErrorNamingIt) {
  EXPECT_EQ(bench("--out " + (*dir_ / "unknown").string() + " --methods dlo,lomp"), 2);
  const std::string err = readFile(stderrPath());
  EXPECT_EQ(err.rfind("dlo-bench: ", 0), 0u) << err;
  EXPECT_NE(err.find("'lomp'"), std::string::npos) << err;
  EXPECT_NE(err.find("dlo-paper"), std::string::npos) << "should list the known methods: " << err;
  EXPECT_FALSE(fs::exists(*dir_ / "unknown"));
}

TEST_F(DloBenchApp, MissingInputIsAnInputErrorNamingTheFile) {
  const std::string missing = (*dir_ / "no_such.rawlog").string();
  EXPECT_EQ(bench("--out " + (*dir_ / "missing").string(), missing), 1);
  const std::string err = readFile(stderrPath());
  EXPECT_EQ(err.rfind("dlo-bench: ", 0), 0u) << err;
  EXPECT_NE(err.find("no_such.rawlog"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(*dir_ / "missing")) << "no output folder for a run that cannot start";
}

TEST_F(DloBenchApp, CommandLineMistakesExitWithStatus2) {
  EXPECT_EQ(bench("--out " + (*dir_ / "x").string() + " --max-frames-slow zero"), 2);
  EXPECT_NE(readFile(stderrPath()).find("--max-frames-slow"), std::string::npos);
  EXPECT_EQ(bench("--out " + (*dir_ / "x").string() + " --bogus"), 2);
  EXPECT_EQ(bench(""), 2) << "--out is required";
  const std::string help = std::string(DLO_BENCH_BINARY) + " --help > /dev/null";
  EXPECT_EQ(std::system(help.c_str()), 0);
}

}  // namespace
}  // namespace dlo::bench
