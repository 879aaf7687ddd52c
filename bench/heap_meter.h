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

// What a metered run may use; 0: no limit.
struct RunBudget {
  // Wall time, s. Past it the run's stop flag is raised (synth/run_stop.h: long loops
  // poll it) and its operator new throws std::bad_alloc, so it ends with an exception.
  double seconds = 0;
  // Heap held at once, MB (1e6 bytes): an operator new that would pass it throws
  // std::bad_alloc. malloc itself never fails for a budget (C libraries do not check
  // it), nor does new inside an OpenMP region (an exception there ends the program);
  // the run is still marked over its budget. Needs the meter (not in sanitizer builds).
  double memory_mb = 0;
};

struct MeteredRun {
  std::int64_t peak_bytes = -1;  // as peak_heap_bytes
  bool over_time = false;        // the time budget passed while it ran
  bool over_memory = false;      // an allocation was refused for the memory budget
};

// Runs `work` (in its own TBB arena) within `budget`; exceptions from `work`
// propagate (catch them inside `work`: handlers that allocate run after the stop).
MeteredRun run_metered(const std::function<void()>& work, const RunBudget& budget);

// Runs `work` (in its own TBB arena) and returns the most heap bytes it held at once
// above the level at the start (malloc_usable_size of each block); -1 when the meter
// is not available. Exceptions from `work` propagate.
std::int64_t peak_heap_bytes(const std::function<void()>& work);

}  // namespace grapebench
