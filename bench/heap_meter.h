// Peak heap of a piece of work, counting every malloc-family allocation (malloc,
// calloc, realloc, the aligned ones, and operator new, which calls malloc): Eigen's,
// PCL's, CGAL's, OpenCV's and the estimator's own, on the calling thread and on every
// TBB worker that helps it. The program interposes glibc's malloc (heap_meter.cpp);
// the work runs in its own TBB arena, whose observer points each thread that joins it
// at the run's counter. Not counted: threads the work starts outside TBB (OpenMP,
// std::thread) and allocations glibc makes internally (strdup). Sanitizer builds keep
// their own malloc and report no figure.
#pragma once

#include <cstdint>
#include <functional>

namespace grapebench {

// False when the counting allocator is not linked in (sanitizer builds).
bool heap_meter_available();

// Runs `work` (in its own TBB arena) and returns the most heap bytes it held at once
// above the level at the start (malloc_usable_size of each block); -1 when the meter
// is not available. Exceptions from `work` propagate.
std::int64_t peak_heap_bytes(const std::function<void()>& work);

}  // namespace grapebench
