/// \file progress_bar.h
/// \brief A one-line progress bar on stderr for the converters.
#pragma once

#include <chrono>
#include <cstddef>
#include <string>

namespace dlo {

/// Redraws one line on stderr ("\r[#####     ] 12/22 scans"), at most 10 times a second so that
/// drawing never costs more than the work. With total == 0 (unknown length) it shows a count.
/// Disabled, it prints nothing: for --quiet and for logs.
class ProgressBar {
 public:
  ProgressBar(size_t total, std::string unit, bool enabled);
  /// Ends the line if something was drawn and finish() was not called (an error is coming).
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Sets the total once it is known (0: unknown).
  void setTotal(size_t total) { total_ = total; }
  /// Draws `done` of the total if the last draw is older than 0.1 s.
  void update(size_t done);
  /// Draws the final state and ends the line.
  void finish(size_t done);

 private:
  void draw(size_t done);

  size_t total_;
  std::string unit_;
  bool enabled_;
  bool drawn_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point last_;
  std::chrono::steady_clock::time_point start_;  ///< for the rate shown, units per second
};

}  // namespace dlo
