#include "dlo/core/ground_surface.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace dlo {

namespace {

/// Coordinates in units of this many metres keep the quadratic's normal equations well scaled.
constexpr double kUnit = 10.0;
/// Quantile of the nearest cells' heights that starts the ground: most cells near a vehicle are
/// ground, and what is not (cars, walls, bushes) lies above it.
constexpr double kStartQuantile = 0.25;
/// Cells the surface is fitted to, at most: the ground is smooth at the scale of the spacing
/// this leaves (about 1 m within 20 m), and the passes cost in proportion.
constexpr size_t kMaxCandidates = 1000;

/// One pass of the fit: the cells within `range` metres of the origin and `band` metres of the
/// current surface, and the terms fitted to them (3: a plane, 6: a quadratic).
struct Pass {
  double range;
  double band;
  int terms;
};

Eigen::Matrix<double, 6, 1> terms(double x, double y) {
  const double u = x / kUnit, v = y / kUnit;
  Eigen::Matrix<double, 6, 1> t;
  t << 1.0, u, v, u * u, u * v, v * v;
  return t;
}

/// Least squares of the cells of `pass` against the surface `c`; returns false (and leaves `c`)
/// when too few cells take part or the system is singular.
bool refit(const std::vector<GroundCell>& cells, const Pass& pass, Eigen::Matrix<double, 6, 1>& c) {
  // The upper triangle summed by hand: Eigen's rankUpdate() of a 6-vector is a call per cell.
  double A[6][6] = {};
  double b[6] = {};
  const double r2 = pass.range * pass.range;
  const int k = pass.terms;
  int n = 0;
  for (const GroundCell& g : cells) {
    const double x = g.x, y = g.y;
    if (x * x + y * y > r2) continue;
    const Eigen::Matrix<double, 6, 1> t = terms(x, y);
    if (std::abs(g.h - c.dot(t)) > pass.band) continue;
    for (int i = 0; i < k; ++i) {
      for (int j = i; j < k; ++j) A[i][j] += t(i) * t(j);
      b[i] += g.h * t(i);
    }
    ++n;
  }
  // A few times more cells than terms, spread enough to hold each of them.
  if (n < 5 * k) return false;
  Eigen::MatrixXd Ak(k, k);
  Eigen::VectorXd bk(k);
  for (int i = 0; i < k; ++i) {
    bk(i) = b[i];
    for (int j = i; j < k; ++j) Ak(i, j) = Ak(j, i) = A[i][j];
  }
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(Ak);
  if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-9)) return false;
  const Eigen::VectorXd x = ldlt.solve(bk);
  if (!x.allFinite()) return false;
  c.setZero();
  c.head(k) = x;
  return true;
}

/// Keeps every (size / keep)-th cell, in fixed point: deterministic and even over the grid.
void thinEvenly(std::vector<GroundCell>& cells, size_t keep) {
  const size_t n = cells.size();
  if (n <= keep) return;
  for (size_t i = 0; i < keep; ++i) cells[i] = cells[i * n / keep];
  cells.resize(keep);
}

}  // namespace

double GroundSurface::heightAt(double x, double y) const {
  return coefficients.dot(terms(x, y));
}

void fitGroundSurface(const HeightGrid& grid, const GroundSurfaceParams& params,
                      GroundSurface& out) {
  out.found = false;
  out.coefficients.setZero();
  out.cells.clear();
  const GridGeometry& g = grid.geometry();
  const double r_min2 = params.min_range * params.min_range;
  const double r_max2 = params.max_range * params.max_range;
  for (int row = 0; row < g.rows; ++row) {
    const double y = g.cellCentreY(row);
    if (y * y > r_max2) continue;
    for (int col = 0; col < g.cols; ++col) {
      if (!grid.isValid(row, col)) continue;
      const double x = g.cellCentreX(col);
      const double d2 = x * x + y * y;
      if (d2 < r_min2 || d2 > r_max2) continue;
      out.cells.push_back(
          GroundCell{static_cast<float>(x), static_cast<float>(y), grid.height(row, col)});
    }
  }
  thinEvenly(out.cells, kMaxCandidates);
  // The passes widen the area and tighten the band: near the vehicle the ground is close to a
  // plane whatever its shape farther out; a crest or dip bends it by up to half a metre at
  // 10 m on a 20 % grade change, which the quadratic then follows outwards.
  const double near = std::min(params.max_range, std::max(8.0, 2.0 * params.min_range));
  const Pass passes[] = {
      {near, 0.5, 3},
      {0.7 * params.max_range, 0.3, 6},
      {params.max_range, params.band, 6},
  };
  // Scratch kept across calls, used through a plain pointer (see alignToGround()).
  thread_local std::vector<float> height_scratch;
  height_scratch.resize(out.cells.size());
  float* const heights = height_scratch.data();
  size_t nearby = 0;
  for (const GroundCell& c : out.cells) {
    if (c.x * c.x + c.y * c.y <= near * near) heights[nearby++] = c.h;
  }
  if (static_cast<int>(nearby) < params.min_cells) {
    out.cells.clear();
    return;
  }
  float* const q = heights + static_cast<size_t>(kStartQuantile * nearby);
  std::nth_element(heights, q, heights + nearby);
  Eigen::Matrix<double, 6, 1> c = Eigen::Matrix<double, 6, 1>::Zero();
  c(0) = *q;
  for (const Pass& pass : passes) {
    // A quadratic that the cells cannot hold keeps the plane (or surface) of the pass before.
    if (!refit(out.cells, pass, c) && pass.terms == 3) {
      out.cells.clear();
      return;
    }
  }
  const double band = params.band;
  const auto off = std::remove_if(out.cells.begin(), out.cells.end(), [&](const GroundCell& cell) {
    return std::abs(cell.h - c.dot(terms(cell.x, cell.y))) > band;
  });
  out.cells.erase(off, out.cells.end());
  thinEvenly(out.cells, static_cast<size_t>(params.max_cells));
  out.coefficients = c;
  out.found = static_cast<int>(out.cells.size()) >= params.min_cells;
  if (!out.found) out.cells.clear();
}

}  // namespace dlo
