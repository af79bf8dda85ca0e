// The heap limit of the fuzz targets (allocation_limit.cpp): what a target tells it, and asks.
#pragma once

#include <new>

namespace dlo::fuzz {

/// Starts the heap budget of one input: from here the input may grow the live heap by
/// allocation_limit.cpp's budget. Call first in LLVMFuzzerTestOneInput.
void startInput();

/// Whether the current input used up its heap budget. Its std::bad_alloc may then come out of
/// whatever was allocating, as in a process out of memory, and is not a failure of the reader;
/// one without it (a single request over the block limit, e.g. a count from the file reserved
/// unchecked) is.
bool heapBudgetExhausted();

/// Runs `read` on one input under the heap budget: a std::bad_alloc is accepted once the budget
/// is used up, and passed on (a crash) otherwise.
template <typename Read>
void withHeapBudget(Read read) {
  startInput();
  try {
    read();
  } catch (const std::bad_alloc&) {
    if (!heapBudgetExhausted()) throw;
  }
}

}  // namespace dlo::fuzz
