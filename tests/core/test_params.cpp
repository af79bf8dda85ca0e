// DloParams validation: one sentence naming the key and the accepted range.
#include <gtest/gtest.h>

#include "dlo/core/dlo_params.h"

namespace dlo {
namespace {

TEST(DloParams, DefaultsAreTheOnesOfThePaperAndValid) {
  const DloParams p;
  EXPECT_EQ(p.grid.cols, 400);
  EXPECT_EQ(p.grid.rows, 400);
  EXPECT_DOUBLE_EQ(p.grid.resolution, 0.1);
  EXPECT_EQ(p.grid.min_points, 3);
  EXPECT_EQ(p.validate(), "");
}

TEST(DloParams, RejectsAnUnknownDofNamingTheKey) {
  DloParams p;
  p.solver.dof = 4;
  EXPECT_NE(p.validate().find("solver.dof"), std::string::npos);
  EXPECT_NE(p.validate().find("3 or 6"), std::string::npos);
}

TEST(DloParams, RejectsACoarseStepOfHalfACellOrMoreAndNaN) {
  DloParams p;
  p.solver.coarse_step = 0.0;  // 0: the coarse levels use the finest level's criteria
  EXPECT_EQ(p.validate(), "");
  p.solver.coarse_step = 0.6;
  EXPECT_NE(p.validate().find("solver.coarse_step"), std::string::npos);
  EXPECT_NE(p.validate().find("[0, 0.5]"), std::string::npos);
  p.solver.coarse_step = std::nan("");
  EXPECT_NE(p.validate().find("solver.coarse_step"), std::string::npos);
}

TEST(DloParams, RejectsNonPositiveResolutionAndNaN) {
  DloParams p;
  p.grid.resolution = 0.0;
  EXPECT_NE(p.validate().find("grid.resolution"), std::string::npos);
  p.grid.resolution = std::nan("");
  EXPECT_NE(p.validate().find("grid.resolution"), std::string::npos);
}

TEST(DloParams, RejectsTooManyLevelsForTheGrid) {
  DloParams p;
  p.grid.cols = 32;
  p.grid.levels = 5;
  EXPECT_NE(p.validate().find("grid.levels"), std::string::npos);
}

TEST(DloParams, RejectsAnInvertedHeightBand) {
  DloParams p;
  p.grid.min_z = 2.0;
  p.grid.max_z = 1.0;
  EXPECT_NE(p.validate().find("grid.max_z"), std::string::npos);
}

}  // namespace
}  // namespace dlo
