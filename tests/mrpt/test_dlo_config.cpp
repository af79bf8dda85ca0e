// dlo::DloParams from and to MRPT INI text, and --set overrides.
#include <gtest/gtest.h>

#include <mrpt/config/CConfigFileMemory.h>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "dlo/files/error.h"
#include "dlo/mrpt/dlo_config.h"

namespace dlo {
namespace {

/// Every field, so that a field the loader forgets shows up here.
void expectSameParams(const DloParams& a, const DloParams& b) {
  EXPECT_EQ(a.grid.cols, b.grid.cols);
  EXPECT_EQ(a.grid.rows, b.grid.rows);
  EXPECT_EQ(a.grid.resolution, b.grid.resolution);
  EXPECT_EQ(a.grid.min_points, b.grid.min_points);
  EXPECT_EQ(a.grid.min_z, b.grid.min_z);
  EXPECT_EQ(a.grid.max_z, b.grid.max_z);
  EXPECT_EQ(a.grid.levels, b.grid.levels);
  EXPECT_EQ(a.selection.min_gradient, b.selection.min_gradient);
  EXPECT_EQ(a.selection.block_size, b.selection.block_size);
  EXPECT_EQ(a.selection.max_cells, b.selection.max_cells);
  EXPECT_EQ(a.selection.ground_stride, b.selection.ground_stride);
  EXPECT_EQ(a.selection.centroid_levels, b.selection.centroid_levels);
  EXPECT_EQ(a.solver.dof, b.solver.dof);
  EXPECT_EQ(a.solver.max_iterations, b.solver.max_iterations);
  EXPECT_EQ(a.solver.huber_delta, b.solver.huber_delta);
  EXPECT_EQ(a.solver.max_residual, b.solver.max_residual);
  EXPECT_EQ(a.solver.min_step_translation, b.solver.min_step_translation);
  EXPECT_EQ(a.solver.min_step_rotation, b.solver.min_step_rotation);
  EXPECT_EQ(a.solver.coarse_step, b.solver.coarse_step);
  EXPECT_EQ(a.solver.min_cells, b.solver.min_cells);
  EXPECT_EQ(a.solver.degeneracy_eigen_ratio, b.solver.degeneracy_eigen_ratio);
  EXPECT_EQ(a.solver.rotation_scale, b.solver.rotation_scale);
}

/// Valid values, each different from its default.
DloParams nonDefaultParams() {
  DloParams p;
  p.grid.cols = 320;
  p.grid.rows = 240;
  p.grid.resolution = 0.15;
  p.grid.min_points = 2;
  p.grid.min_z = -3.5;
  p.grid.max_z = 4.25;
  p.grid.levels = 3;
  p.selection.min_gradient = 1.0 / 3.0;  // not exact in decimal: the dump must still round-trip
  p.selection.block_size = 4;
  p.selection.max_cells = 5000;
  p.selection.ground_stride = 8;
  p.selection.centroid_levels = 1;
  p.solver.dof = 6;
  p.solver.max_iterations = 25;
  p.solver.huber_delta = 0.2;
  p.solver.max_residual = 1.5;
  p.solver.min_step_translation = 2e-4;
  p.solver.min_step_rotation = 3e-5;
  p.solver.coarse_step = 0.02;
  p.solver.min_cells = 40;
  p.solver.degeneracy_eigen_ratio = 2e-3;
  p.solver.rotation_scale = 12.0;
  return p;
}

const char* const kAllSections = R"(
[grid]
cols = 320
rows = 240
resolution = 0.15
min_points = 2
min_z = -3.5
max_z = 4.25
levels = 3

[selection]
min_gradient = 0.33333333333333331
block_size = 4
max_cells = 5000
ground_stride = 8
centroid_levels = 1

[solver]
dof = 6
max_iterations = 25
huber_delta = 0.2
max_residual = 1.5
min_step_translation = 2e-4
min_step_rotation = 3e-5
coarse_step = 0.02
min_cells = 40
degeneracy_eigen_ratio = 2e-3
rotation_scale = 12
)";

class TempFile {
 public:
  explicit TempFile(const std::string& text)
      : path_(testing::TempDir() + "dlo_config_test_" +
              testing::UnitTest::GetInstance()->current_test_info()->name() + ".ini") {
    std::ofstream(path_) << text;
  }
  ~TempFile() { std::remove(path_.c_str()); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// The message of the InputError `f` throws, or "" if it throws none.
template <typename F>
std::string inputErrorOf(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DloConfig, LoadsEveryKeyOfAFileWithAllSections) {
  TempFile file(kAllSections);
  expectSameParams(loadDloParamsFile(file.path()), nonDefaultParams());
}

TEST(DloConfig, MissingKeysKeepTheirDefaults) {
  mrpt::config::CConfigFileMemory ini("[solver]\ndof = 6\n");
  DloParams expected;
  expected.solver.dof = 6;
  expectSameParams(loadDloParams(ini), expected);
  expectSameParams(loadDloParams(mrpt::config::CConfigFileMemory("")), DloParams());
}

TEST(DloConfig, OutOfRangeValueThrowsNamingTheKeyAndRange) {
  mrpt::config::CConfigFileMemory ini("[grid]\nresolution = -0.1\n");
  const std::string msg = inputErrorOf([&] { loadDloParams(ini); });
  EXPECT_NE(msg.find("grid.resolution"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(0, 10]"), std::string::npos) << msg;
}

TEST(DloConfig, UnparsableValueThrowsNamingTheKey) {
  for (const char* text : {"[solver]\nmax_iterations = many\n", "[solver]\nmax_iterations = 2.5\n",
                           "[selection]\nmin_gradient = 0.3x\n"}) {
    const std::string msg =
        inputErrorOf([&] { loadDloParams(mrpt::config::CConfigFileMemory(text)); });
    const bool names_key = msg.find("solver.max_iterations") != std::string::npos ||
                           msg.find("selection.min_gradient") != std::string::npos;
    EXPECT_TRUE(names_key) << text << " -> " << msg;
  }
}

TEST(DloConfig, FileErrorsNameTheFileAndTheKey) {
  TempFile file("[solver]\ndof = 4\n");
  const std::string msg = inputErrorOf([&] { loadDloParamsFile(file.path()); });
  EXPECT_NE(msg.find(file.path()), std::string::npos) << msg;
  EXPECT_NE(msg.find("solver.dof"), std::string::npos) << msg;
}

TEST(DloConfig, MissingFileThrowsNamingIt) {
  const std::string msg = inputErrorOf([] { loadDloParamsFile("/nonexistent/dlo.ini"); });
  EXPECT_NE(msg.find("/nonexistent/dlo.ini"), std::string::npos) << msg;
}

TEST(DloConfig, UnknownKeyInASectionIsRejected) {
  mrpt::config::CConfigFileMemory ini("[grid]\nresolutoin = 0.2\n");
  const std::string msg = inputErrorOf([&] { loadDloParams(ini); });
  EXPECT_NE(msg.find("grid.resolutoin"), std::string::npos) << msg;
}

TEST(DloConfig, OtherSectionsAreLeftToTheirOwners) {
  mrpt::config::CConfigFileMemory ini("[ICP]\nmaxIterations = 10\n[grid]\ncols = 200\n");
  EXPECT_EQ(loadDloParams(ini).grid.cols, 200);
}

TEST(DloConfig, PrefixSelectsDottedSections) {
  mrpt::config::CConfigFileMemory ini("[grid]\ncols = 100\n[dlo.grid]\ncols = 200\n");
  EXPECT_EQ(loadDloParams(ini, "dlo").grid.cols, 200);
  EXPECT_EQ(loadDloParams(ini).grid.cols, 100);
}

TEST(DloConfig, SetOverridesApplyInOrder) {
  DloParams p;
  applyDloParamOverrides(p, {"solver.dof=6", "grid.resolution = 0.2", "solver.dof=3"});
  EXPECT_EQ(p.solver.dof, 3);
  EXPECT_DOUBLE_EQ(p.grid.resolution, 0.2);
}

TEST(DloConfig, SetRejectsUnknownSectionOrKeyNamingIt) {
  DloParams p;
  std::string msg = inputErrorOf([&] { applyDloParamOverrides(p, {"solver.dfo=6"}); });
  EXPECT_NE(msg.find("solver.dfo"), std::string::npos) << msg;
  msg = inputErrorOf([&] { applyDloParamOverrides(p, {"solve.dof=6"}); });
  EXPECT_NE(msg.find("solve.dof"), std::string::npos) << msg;
  msg = inputErrorOf([&] { applyDloParamOverrides(p, {"dof=6"}); });
  EXPECT_NE(msg.find("dof=6"), std::string::npos) << msg;
  expectSameParams(p, DloParams());
}

TEST(DloConfig, SetRejectsInvalidValueAndLeavesParamsUntouched) {
  DloParams p;
  const std::string msg = inputErrorOf([&] {
    applyDloParamOverrides(p, {"grid.cols=100", "solver.dof=5"});
  });
  EXPECT_NE(msg.find("solver.dof"), std::string::npos) << msg;
  expectSameParams(p, DloParams());
}

TEST(DloConfig, DumpThenLoadGivesTheSameParams) {
  const DloParams original = nonDefaultParams();
  const std::string text = dloParamsToIni(original);
  expectSameParams(loadDloParams(mrpt::config::CConfigFileMemory(text)), original);
}

TEST(DloConfig, DumpHasOneCommentLinePerKey) {
  std::istringstream in(dloParamsToIni(DloParams()));
  std::string line, previous;
  int keys = 0;
  while (std::getline(in, line)) {
    if (line.find(" = ") != std::string::npos) {
      ++keys;
      EXPECT_EQ(previous.rfind("; ", 0), 0u) << "no comment before: " << line;
    }
    previous = line;
  }
  EXPECT_EQ(keys, 22);
}

TEST(DloConfig, SaveThenLoadGivesTheSameParams) {
  const DloParams original = nonDefaultParams();
  mrpt::config::CConfigFileMemory ini;
  saveDloParams(original, ini, "dlo");
  expectSameParams(loadDloParams(ini, "dlo"), original);
}

}  // namespace
}  // namespace dlo

namespace dlo {
namespace {

TEST(DloConfig, TheShippedConfigFileHoldsExactlyTheDefaults) {
  const DloParams loaded = loadDloParamsFile(std::string(DLO_SOURCE_DIR) + "/config/dlo.ini");
  EXPECT_EQ(dloParamsToIni(loaded), dloParamsToIni(DloParams()));
}

}  // namespace
}  // namespace dlo
