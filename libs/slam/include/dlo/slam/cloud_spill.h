/// \file cloud_spill.h
/// \brief An anonymous temporary file that holds keyframe clouds a long run no longer needs in
/// memory, so that resident memory stays flat however many keyframes a run makes.
#pragma once

#include <cstdint>
#include <cstdio>
#include <mutex>

#include "dlo/core/weighted_cloud.h"

namespace dlo {

/// Where a spilled cloud lies in its CloudSpill.
struct CloudSlot {
  std::uint64_t offset = 0;  ///< bytes from the start of the file
  std::uint64_t count = 0;   ///< points
};

/// Append-only store of weighted clouds in an unnamed temporary file (std::tmpfile: in the
/// system's temporary folder, removed by the system when the process ends, even on a crash).
/// Clouds are written once and read back by slot. Thread-safe.
class CloudSpill {
 public:
  /// Opens the temporary file.
  /// \throws std::runtime_error if the system cannot create one.
  CloudSpill();
  ~CloudSpill();
  CloudSpill(const CloudSpill&) = delete;
  CloudSpill& operator=(const CloudSpill&) = delete;

  /// Appends `cloud` and returns where it lies.
  /// \throws std::runtime_error if the file cannot grow (disk full), naming the size.
  CloudSlot write(const WeightedCloud& cloud);
  /// The cloud written at `slot`.
  /// \throws std::runtime_error if it cannot be read back.
  WeightedCloud read(const CloudSlot& slot) const;
  /// Bytes written so far.
  std::uint64_t bytes() const;

 private:
  std::FILE* file_ = nullptr;
  std::uint64_t end_ = 0;
  mutable std::mutex mutex_;
};

}  // namespace dlo
