// Linked into every fuzz target: the C++ heap is limited like that of a small machine, and
// running out of it throws std::bad_alloc, as the C++ runtime does when the system refuses
// memory, instead of ending the process.
//
// Why: MRPT's deserializers size containers from counts stored in the file before reading the
// elements (an MRPT limitation that DLO cannot guard against without re-implementing MRPT's
// serialization), so a corrupt rawlog asks for gigabytes, in one block or in millions of small
// ones; RawlogScanSource catches the failure and reports a corrupt entry. Without this, such an
// input ends the fuzzer instead:
// - ASan's operator new reports "out of memory" and aborts, even with allocator_may_return_null;
// - mrpt::aligned_malloc (point maps) returns the null of a failed aligned_alloc, which MRPT's
//   aligned_allocator_cpp11 hands to std::vector unchecked: a null dereference (MRPT bug);
// - millions of small blocks exceed libFuzzer's -rss_limit_mb.
// So operator new/delete and mrpt::aligned_malloc/calloc/free are replaced here (the executable's
// definitions interpose ASan's weak ones and MRPT's shared-library ones): a request over
// kMaxBlockBytes throws bad_alloc, and so does one that would grow the live heap since the input
// started beyond a budget (MRPT's memory pools keep blocks of earlier inputs, which are not held
// against the next one). See allocation_limit.h for what the targets make of it.
//
// Libraries that call malloc themselves (OpenCV's cv::fastMalloc, behind MRPT's images) are not
// served from here: run_fuzz.sh gives ASan the same block limit for them (max_allocation_size_mb,
// allocator_may_return_null), so that a refused malloc returns null and the library throws.
//
// Blocks come from malloc, which ASan intercepts, so overflows, use-after-free and leaks are still
// detected; only ASan's new/free mismatch check is lost (run_fuzz.sh sets
// alloc_dealloc_mismatch=0).
#include "allocation_limit.h"

#include <malloc.h>
#include <mrpt/core/aligned_allocator.h>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>

namespace {

/// No input of a few kilobytes legitimately needs one block this large...
constexpr std::size_t kMaxBlockBytes = std::size_t{64} << 20;
/// ...nor to grow the live heap by more than this with blocks of kLargeBlockBytes or more...
constexpr std::size_t kBudgetBytes = std::size_t{128} << 20;
constexpr std::size_t kLargeBlockBytes = std::size_t{1} << 20;
/// ...nor by more than this at all (millions of small blocks, e.g. a std::deque sized from the
/// file). Small blocks are refused only beyond it: they are also what error handling allocates
/// (MRPT builds its exceptions with call stacks, in places where a bad_alloc ends the process),
/// and MRPT's memory pools keep large blocks of the input's earlier objects.
constexpr std::size_t kFloodBytes = std::size_t{384} << 20;

std::atomic<std::size_t> live_bytes{0};
std::atomic<std::size_t> input_start_bytes{0};
std::atomic<bool> budget_exhausted{false};

void* allocate(std::size_t size, std::size_t alignment) {
  if (size == 0) size = 1;
  if (size > kMaxBlockBytes) return nullptr;
  // Not while an exception unwinds the stack: destructors may allocate (MRPT's 3D range scan
  // resizes buffers in its destructor to donate them to a memory pool), in proportion to what
  // was allocated before, and a bad_alloc there would end the process.
  const std::size_t start = input_start_bytes.load();
  const std::size_t grown = live_bytes.load() > start ? live_bytes.load() - start : 0;
  const std::size_t limit = size >= kLargeBlockBytes ? kBudgetBytes : kFloodBytes;
  if (std::uncaught_exceptions() == 0 && grown + size > limit) {
    budget_exhausted = true;
    return nullptr;
  }
  void* p = nullptr;
  if (alignment <= alignof(std::max_align_t)) {
    p = std::malloc(size);
  } else if (posix_memalign(&p, alignment, size) != 0) {
    p = nullptr;
  }
  if (p) live_bytes += malloc_usable_size(p);
  return p;
}

void* allocateOrThrow(std::size_t size, std::size_t alignment) {
  void* p = allocate(size, alignment);
  if (!p) throw std::bad_alloc();
  return p;
}

void release(void* p) noexcept {
  if (!p) return;
  live_bytes -= malloc_usable_size(p);
  std::free(p);
}

}  // namespace

void* operator new(std::size_t size) {
  return allocateOrThrow(size, 0);
}
void* operator new[](std::size_t size) {
  return allocateOrThrow(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a) {
  return allocateOrThrow(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a) {
  return allocateOrThrow(size, static_cast<std::size_t>(a));
}
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return allocate(size, 0);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
  return allocate(size, 0);
}
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(size, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocate(size, static_cast<std::size_t>(a));
}

void operator delete(void* p) noexcept {
  release(p);
}
void operator delete[](void* p) noexcept {
  release(p);
}
void operator delete(void* p, std::size_t) noexcept {
  release(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  release(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  release(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  release(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  release(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  release(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  release(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  release(p);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  release(p);
}
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept {
  release(p);
}

void* mrpt::aligned_malloc(std::size_t size, std::size_t alignment) {
  return allocateOrThrow(size, alignment);
}
void* mrpt::aligned_calloc(std::size_t size, std::size_t alignment) {
  return std::memset(allocateOrThrow(size, alignment), 0, size);
}
void mrpt::aligned_free(void* p) {
  release(p);
}

void dlo::fuzz::startInput() {
  input_start_bytes = live_bytes.load();
  budget_exhausted = false;
}

bool dlo::fuzz::heapBudgetExhausted() {
  return budget_exhausted;
}
