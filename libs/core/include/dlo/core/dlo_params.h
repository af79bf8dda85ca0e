/// \file dlo_params.h
/// \brief All registration parameters in one place, with validation.
#pragma once

#include <string>

#include "dlo/core/cell_selection.h"
#include "dlo/core/direct_aligner.h"
#include "dlo/core/height_grid.h"

namespace dlo {

/// Every parameter of a DLO registration, grouped by INI section.
struct DloParams {
  HeightGridParams grid;      ///< [grid]
  SelectionParams selection;  ///< [selection]
  SolverParams solver;        ///< [solver]

  /// Empty when all values are acceptable, otherwise one sentence naming the key
  /// (section.key) and the accepted range.
  std::string validate() const;
  /// Whether ground cells are selected (6-DoF).
  bool includeGround() const { return solver.dof == 6; }
};

}  // namespace dlo
