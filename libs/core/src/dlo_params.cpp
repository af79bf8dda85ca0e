#include "dlo/core/dlo_params.h"

#include "dlo/core/range_message.h"

namespace dlo {

std::string DloParams::validate() const {
  if (grid.cols < 8 || grid.cols > 20000) return outOfRange("grid.cols", grid.cols, "8..20000");
  if (grid.rows < 8 || grid.rows > 20000) return outOfRange("grid.rows", grid.rows, "8..20000");
  if (!(grid.resolution > 0.0 && grid.resolution <= 10.0))
    return outOfRange("grid.resolution", grid.resolution, "a value in (0, 10] metres");
  if (grid.min_points < 1 || grid.min_points > 1000)
    return outOfRange("grid.min_points", grid.min_points, "1..1000");
  if (!(grid.min_z < grid.max_z))
    return outOfRange("grid.max_z", grid.max_z, "a height above grid.min_z");
  if (grid.levels < 1 || grid.levels > 8) return outOfRange("grid.levels", grid.levels, "1..8");
  if ((grid.cols >> (grid.levels - 1)) < 4 || (grid.rows >> (grid.levels - 1)) < 4)
    return outOfRange("grid.levels", grid.levels,
                      "few enough levels that the coarsest grid keeps at least 4x4 cells");
  if (!(selection.min_gradient >= 0.0))
    return outOfRange("selection.min_gradient", selection.min_gradient, "a value >= 0");
  if (selection.block_size < 1 || selection.block_size > 64)
    return outOfRange("selection.block_size", selection.block_size, "1..64");
  if (selection.max_cells < 1)
    return outOfRange("selection.max_cells", selection.max_cells, "a positive count");
  if (selection.centroid_levels < 0)
    return outOfRange("selection.centroid_levels", selection.centroid_levels, "0 (off) or more");
  if (selection.ground_stride < 0)
    return outOfRange("selection.ground_stride", selection.ground_stride, "0 (off) or more");
  if (solver.dof != 3 && solver.dof != 6) return outOfRange("solver.dof", solver.dof, "3 or 6");
  if (solver.max_iterations < 1 || solver.max_iterations > 1000)
    return outOfRange("solver.max_iterations", solver.max_iterations, "1..1000");
  if (!(solver.huber_delta > 0.0))
    return outOfRange("solver.huber_delta", solver.huber_delta, "a positive height in metres");
  if (!(solver.max_residual > 0.0))
    return outOfRange("solver.max_residual", solver.max_residual, "a positive height in metres");
  if (!(solver.min_step_translation > 0.0))
    return outOfRange("solver.min_step_translation", solver.min_step_translation, "> 0");
  if (!(solver.min_step_rotation > 0.0))
    return outOfRange("solver.min_step_rotation", solver.min_step_rotation, "> 0");
  if (!(solver.coarse_step >= 0.0 && solver.coarse_step <= 0.5))
    return outOfRange("solver.coarse_step", solver.coarse_step, "[0, 0.5] (a fraction of a cell)");
  if (solver.min_cells < 1) return outOfRange("solver.min_cells", solver.min_cells, ">= 1");
  if (!(solver.degeneracy_eigen_ratio >= 0.0 && solver.degeneracy_eigen_ratio < 1.0))
    return outOfRange("solver.degeneracy_eigen_ratio", solver.degeneracy_eigen_ratio, "[0, 1)");
  if (!(solver.rotation_scale > 0.0))
    return outOfRange("solver.rotation_scale", solver.rotation_scale, "a positive length");
  return {};
}

}  // namespace dlo
