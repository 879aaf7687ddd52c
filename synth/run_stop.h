// The stop signal of an estimator run: the harness raises it when the run passes its
// time budget (bench/heap_meter.h), and long loops of the algorithms poll it, so an
// estimator that never allocates still ends. Allocations of a stopped run fail too.
#pragma once

#include <atomic>
#include <stdexcept>

namespace grapebench {

struct StopRequested : std::runtime_error {
  StopRequested() : std::runtime_error("stopped: over its time budget") {}
};

// The stop flag of the run this thread works for; nullptr outside a budgeted run.
// Set by the harness on the run's thread and on every TBB worker that joins it.
inline thread_local const std::atomic<bool>* tls_run_stop = nullptr;

// Throws StopRequested when this thread's run has been told to stop. Cheap (a
// thread-local load): call it once per iteration of a long loop.
inline void throw_if_stop_requested() {
  if (tls_run_stop && tls_run_stop->load(std::memory_order_relaxed)) throw StopRequested();
}

}  // namespace grapebench
