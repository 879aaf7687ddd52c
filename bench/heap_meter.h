// Peak heap of a piece of work on the calling thread: the program replaces global
// operator new/delete with counting wrappers around malloc (heap_meter.cpp).
// Allocations by malloc directly (some C libraries) are not seen; sanitizer builds
// keep their own operator new and report no figure.
#pragma once

#include <cstdint>

namespace grapebench {

// False when the counting allocator is not linked in (sanitizer builds).
bool heap_meter_available();

// Starts a measurement on this thread; peak_bytes() is the most heap this thread held
// above the level at start() since then.
class HeapMeter {
 public:
  HeapMeter();
  std::int64_t peak_bytes() const;

 private:
  std::int64_t base_;
};

}  // namespace grapebench
