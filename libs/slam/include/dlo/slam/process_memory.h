/// \file process_memory.h
/// \brief Resident memory of this process, from /proc/self/status (Linux).
#pragma once

namespace dlo {

/// Current resident set size (VmRSS), megabytes; 0 if unknown.
double residentMemoryMb();

/// Peak resident set size since the process started or since resetPeakMemory() (VmHWM),
/// megabytes; falls back to getrusage's ru_maxrss when /proc is unavailable.
double peakResidentMemoryMb();

/// Resets the peak to the current resident size (writes "5" to /proc/self/clear_refs), so that
/// a forked child measures its own peak, not its parent's. \return false if not supported.
bool resetPeakMemory();

}  // namespace dlo
