/// \file stage_times.h
/// \brief Wall-clock time per pipeline stage, in milliseconds.
#pragma once

#include <chrono>

namespace dlo {

/// Time spent per stage of a registration, milliseconds.
struct StageTimes {
  double grid_ms = 0.0;       ///< rasterising points into the pyramid
  double gradients_ms = 0.0;  ///< gradients and reference samplers
  double selection_ms = 0.0;  ///< semi-dense cell selection
  double solve_ms = 0.0;      ///< Gauss-Newton, all levels

  double totalMs() const { return grid_ms + gradients_ms + selection_ms + solve_ms; }
  StageTimes& operator+=(const StageTimes& o) {
    grid_ms += o.grid_ms;
    gradients_ms += o.gradients_ms;
    selection_ms += o.selection_ms;
    solve_ms += o.solve_ms;
    return *this;
  }
};

/// Milliseconds since construction.
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double elapsedMs() const {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_)
        .count();
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

}  // namespace dlo
