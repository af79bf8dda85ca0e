// Gradients on supported cells only, and the semi-dense selection.
#include <gtest/gtest.h>

#include <set>

#include "dlo/core/cell_selection.h"
#include "dlo/core/gradient_field.h"

namespace dlo {
namespace {

/// A fully measured grid with heights from f(x, y) at cell centres.
template <typename F>
HeightGrid gridOf(const GridGeometry& geo, F f, std::vector<std::uint32_t> counts = {}) {
  std::vector<float> h(geo.cellCount());
  if (counts.empty()) counts.assign(geo.cellCount(), 5u);
  for (int r = 0; r < geo.rows; ++r)
    for (int c = 0; c < geo.cols; ++c)
      h[r * geo.cols + c] = static_cast<float>(f(geo.cellCentreX(c), geo.cellCentreY(r)));
  return HeightGrid::fromCells(geo, h, counts, 3);
}

TEST(GradientField, CentralDifferencesRecoverTheSlopeOfARampInMetresPerMetre) {
  const GridGeometry geo = GridGeometry::centred(20, 20, 0.1);
  const GradientField g =
      computeGradients(gridOf(geo, [](double x, double y) { return 0.3 * x - 0.2 * y + 1.0; }));
  ASSERT_TRUE(g.isValid(10, 10));
  EXPECT_NEAR(g.at(10, 10).gx, 0.3f, 1e-4f);
  EXPECT_NEAR(g.at(10, 10).gy, -0.2f, 1e-4f);
  EXPECT_NEAR(g.magnitude(10, 10), std::sqrt(0.13f), 1e-4f);
}

TEST(GradientField, IsMaskedNextToEmptyCellsAndOnTheBorder) {
  const GridGeometry geo = GridGeometry::centred(10, 10, 1.0);
  std::vector<std::uint32_t> counts(geo.cellCount(), 5u);
  counts[5 * 10 + 6] = 0;  // an empty cell right of (5, 5)
  const GradientField g = computeGradients(gridOf(
      geo, [](double x, double) { return x; }, counts));
  EXPECT_FALSE(g.isValid(5, 5));  // its neighbour is empty: no artificial edge
  EXPECT_FALSE(g.isValid(5, 7));
  EXPECT_FALSE(g.isValid(4, 6));
  EXPECT_TRUE(g.isValid(3, 3));
  EXPECT_FALSE(g.isValid(0, 3));  // border: no central difference
  EXPECT_FALSE(g.isValid(3, 9));
}

TEST(CellSelection, PicksCellsAlongAStepAndNoneOnFlatGround) {
  const GridGeometry geo = GridGeometry::centred(40, 40, 0.1);
  // A 1 m wall face along x = 0.
  const HeightGrid grid = gridOf(geo, [](double x, double) { return x < 0.0 ? 0.0 : 1.0; });
  const GradientField g = computeGradients(grid);
  SelectionParams p;
  p.block_size = 1;
  const std::vector<SelectedCell> cells = selectHighGradientCells(grid, g, p, false);
  ASSERT_FALSE(cells.empty());
  for (const SelectedCell& c : cells) EXPECT_LT(std::abs(c.x), 0.11f);
  // Both columns adjacent to the step, on every interior row.
  EXPECT_EQ(cells.size(), 2u * 38u);
}

TEST(CellSelection, KeepsOneCellPerBlockForEvenCoverage) {
  const GridGeometry geo = GridGeometry::centred(40, 40, 0.1);
  const HeightGrid grid = gridOf(geo, [](double x, double y) { return 0.5 * x + 0.5 * y; });
  const GradientField g = computeGradients(grid);
  SelectionParams p;
  p.block_size = 4;
  const std::vector<SelectedCell> cells = selectHighGradientCells(grid, g, p, false);
  EXPECT_EQ(cells.size(), 100u);  // (40 / 4)^2 blocks, each with a strong gradient
  std::set<std::pair<int, int>> blocks;
  for (const SelectedCell& c : cells) {
    blocks.insert({static_cast<int>(std::floor((c.x + 2.0) / 0.4)),
                   static_cast<int>(std::floor((c.y + 2.0) / 0.4))});
  }
  EXPECT_EQ(blocks.size(), cells.size());
}

TEST(CellSelection, CapsTheCountByEvenThinning) {
  const GridGeometry geo = GridGeometry::centred(100, 100, 0.1);
  const HeightGrid grid = gridOf(geo, [](double x, double) { return 2.0 * x; });
  const GradientField g = computeGradients(grid);
  SelectionParams p;
  p.block_size = 1;
  p.max_cells = 500;
  const std::vector<SelectedCell> cells = selectHighGradientCells(grid, g, p, false);
  ASSERT_EQ(cells.size(), 500u);
  // Thinning keeps the spread: the selection still spans most of the grid in y.
  float ymin = 1e9f, ymax = -1e9f;
  for (const SelectedCell& c : cells) {
    ymin = std::min(ymin, c.y);
    ymax = std::max(ymax, c.y);
  }
  EXPECT_GT(ymax - ymin, 9.0f);
}

TEST(CellSelection, AddsAGroundLatticeOnlyWhenAsked) {
  const GridGeometry geo = GridGeometry::centred(30, 30, 0.1);
  const HeightGrid flat = gridOf(geo, [](double, double) { return -1.7; });
  const GradientField g = computeGradients(flat);
  SelectionParams p;
  p.ground_stride = 5;
  EXPECT_TRUE(selectHighGradientCells(flat, g, p, false).empty());
  const std::vector<SelectedCell> ground = selectHighGradientCells(flat, g, p, true);
  EXPECT_EQ(ground.size(), 36u);  // a 6 x 6 lattice
  for (const SelectedCell& c : ground) EXPECT_FLOAT_EQ(c.h, -1.7f);
}

}  // namespace
}  // namespace dlo
