#include "dlo/mrpt/dlo_config.h"

#include "dlo/files/error.h"
#include "dlo/mrpt/param_table.h"

namespace dlo {

namespace {

template <typename G, typename T>
ParamField<DloParams> field(const char* section, const char* key, G DloParams::*group, T G::*member,
                            const char* doc) {
  return paramField<DloParams>(section, key, group, member, doc);
}

const std::vector<ParamField<DloParams>>& fields() {
  using D = DloParams;
  using G = HeightGridParams;
  using S = SelectionParams;
  using V = SolverParams;
  static const std::vector<ParamField<DloParams>> table = {
      field("grid", "cols", &D::grid, &G::cols, "cells along x (paper: 400)"),
      field("grid", "rows", &D::grid, &G::rows, "cells along y (paper: 400)"),
      field("grid", "resolution", &D::grid, &G::resolution,
            "metres per cell at the finest level (paper: 0.10)"),
      field("grid", "min_points", &D::grid, &G::min_points,
            "a cell needs at least this many points to be valid (paper: 3)"),
      field("grid", "min_z", &D::grid, &G::min_z,
            "points below this height (m, grid frame) are ignored"),
      field("grid", "max_z", &D::grid, &G::max_z,
            "points above this height (m, grid frame) are ignored"),
      field("grid", "levels", &D::grid, &G::levels,
            "pyramid levels; level k has cells 2^k times larger"),
      field("selection", "min_gradient", &D::selection, &S::min_gradient,
            "|grad H| threshold, metres of height per metre"),
      field("selection", "block_size", &D::selection, &S::block_size,
            "at most one gradient cell per block x block cells (even coverage)"),
      field("selection", "max_cells", &D::selection, &S::max_cells,
            "cap on gradient cells per level; thinned evenly beyond it"),
      field("selection", "ground_stride", &D::selection, &S::ground_stride,
            "6-DoF only: also take every n-th valid cell (any gradient) to observe z, roll and "
            "pitch from the ground; 0 disables"),
      field("selection", "centroid_levels", &D::selection, &S::centroid_levels,
            "the finest levels whose cells are compared where their points are (their "
            "centroids), in the scan and the reference alike, so that a cell a spinning "
            "sensor's ring samples on one side (a kerb's edge) is not biased by the part it did "
            "not see (ignored against the scan map); 0: at the cells' centres (the paper). "
            "dlo-localize: above 0, the scan's cells at their centroids against the map's "
            "heights moved to its cells' centres (from the map's heightmap_centroids.bin; a map "
            "without it is compared at the centres)"),
      field("solver", "dof", &D::solver, &V::dof,
            "3 (x, y, yaw) or 6 (full SE(3), z, roll and pitch observed from the ground)"),
      field("solver", "max_iterations", &D::solver, &V::max_iterations, "per pyramid level"),
      field("solver", "huber_delta", &D::solver, &V::huber_delta,
            "robust kernel width on the height error, metres"),
      field("solver", "max_residual", &D::solver, &V::max_residual,
            "residuals beyond this (m) are outliers, weight 0"),
      field("solver", "min_step_translation", &D::solver, &V::min_step_translation,
            "convergence: translation update below this (m)"),
      field("solver", "min_step_rotation", &D::solver, &V::min_step_rotation,
            "convergence: rotation update below this (rad)"),
      field("solver", "coarse_step", &D::solver, &V::coarse_step,
            "convergence of the coarse levels: update below this fraction of their cell size"),
      field("solver", "min_cells", &D::solver, &V::min_cells,
            "fewer usable cells than this: degenerate"),
      field("solver", "degeneracy_eigen_ratio", &D::solver, &V::degeneracy_eigen_ratio,
            "eig_min/eig_max of the scaled Hessian below this: degenerate"),
      field("solver", "rotation_scale", &D::solver, &V::rotation_scale,
            "metres; scales rotations against translations when judging conditioning"),
  };
  return table;
}

const ParamTable<DloParams>& table() {
  static const ParamTable<DloParams> t(fields(), [](const DloParams& p) { return p.validate(); });
  return t;
}

}  // namespace

const std::vector<ParamField<DloParams>>& dloParamFields() {
  return fields();
}

std::string dloSectionName(const std::string& prefix, const std::string& group) {
  return param_text::sectionName(prefix, group);
}

DloParams loadDloParams(const mrpt::config::CConfigFileBase& config, const std::string& prefix,
                        const DloParams& defaults) {
  return table().load(config, prefix, defaults);
}

DloParams loadDloParamsFile(const std::string& path, const std::string& prefix,
                            const DloParams& defaults) {
  return table().loadFile(path, prefix, defaults);
}

void applyDloParamOverrides(DloParams& params, const std::vector<std::string>& assignments) {
  table().applyOverrides(params, assignments);
}

void saveDloParams(const DloParams& params, mrpt::config::CConfigFileBase& config,
                   const std::string& prefix) {
  table().save(params, config, prefix);
}

std::string dloParamsToIni(const DloParams& params, const std::string& prefix) {
  return table().toIni(params, prefix);
}

std::string dloConfigFileText() {
  return param_text::comment(
             "DLO registration parameters (MRPT INI), generated from the parameter table "
             "(docs/parameters.md lists the same). Used by dlo-register --config and by "
             "mrpt::slam::CDirectHeightAligner::TConfigParams::loadFromConfigFile. Every key is "
             "optional: a missing key keeps the default shown here. The defaults follow the "
             "paper (400 x 400 cells of 0.10 m). A value out of range is rejected with a "
             "message naming section.key and the accepted range.") +
         "\n" + dloParamsToIni(DloParams());
}

}  // namespace dlo
