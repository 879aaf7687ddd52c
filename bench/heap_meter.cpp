#include "bench/heap_meter.h"

#include <malloc.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <mutex>
#include <vector>

namespace grapebench {
namespace {

// Live bytes of one metered run and their high-water mark, shared by its threads.
// Counters are pooled and never freed: a TBB worker can linger in a finished run's
// arena without an exit callback, so a thread's pointer may outlive its run; the
// generation tells it the counter has moved on to another run.
struct HeapCounter {
  std::atomic<std::int64_t> live{0}, peak{0};
  std::atomic<std::uint64_t> generation{0};
  void add(std::int64_t n) {
    const std::int64_t now = live.fetch_add(n, std::memory_order_relaxed) + n;
    std::int64_t p = peak.load(std::memory_order_relaxed);
    while (now > p && !peak.compare_exchange_weak(p, now, std::memory_order_relaxed)) {
    }
  }
};

// The run this thread works for: its counter and the counter's generation then.
struct ThreadRun {
  HeapCounter* counter = nullptr;
  std::uint64_t generation = 0;
};
thread_local ThreadRun tls_run;

HeapCounter* active_counter() {
  HeapCounter* c = tls_run.counter;
  return c && c->generation.load(std::memory_order_relaxed) == tls_run.generation ? c : nullptr;
}

// The pool outlives every static destructor (a pointer that is never deleted), so
// counters stay reachable to the end and LeakSanitizer sees no leak.
struct CounterPool {
  std::mutex mutex;
  std::vector<HeapCounter*> free;
};
CounterPool& pool() {
  static CounterPool* p = new CounterPool;
  return *p;
}

HeapCounter* take_counter() {
  CounterPool& p = pool();
  std::lock_guard<std::mutex> lock(p.mutex);
  if (p.free.empty()) return new HeapCounter;
  HeapCounter* c = p.free.back();
  p.free.pop_back();
  return c;
}

void release_counter(HeapCounter* c) {
  c->generation.fetch_add(1);  // threads still pointing here stop counting
  c->live = 0;
  c->peak = 0;
  CounterPool& p = pool();
  std::lock_guard<std::mutex> lock(p.mutex);
  p.free.push_back(c);
}

// Points every worker that joins the run's arena at the run's counter while it is there.
class ArenaCounterObserver : public tbb::task_scheduler_observer {
 public:
  ArenaCounterObserver(tbb::task_arena& arena, ThreadRun run) : tbb::task_scheduler_observer(arena), run_(run) {
    observe(true);
  }
  ~ArenaCounterObserver() override { observe(false); }
  void on_scheduler_entry(bool is_worker) override {
    if (is_worker) tls_run = run_;
  }
  void on_scheduler_exit(bool is_worker) override {
    if (is_worker) tls_run = ThreadRun{};
  }

 private:
  ThreadRun run_;
};

}  // namespace

#ifdef GRAPEBENCH_HEAP_METER
bool heap_meter_available() { return true; }
#else
bool heap_meter_available() { return false; }
#endif

std::int64_t peak_heap_bytes(const std::function<void()>& work) {
  HeapCounter* const counter = take_counter();
  const ThreadRun run{counter, counter->generation.load()};
  const ThreadRun saved = tls_run;
  std::int64_t peak = -1;
  try {
    tbb::task_arena arena;  // the default concurrency, within the run's global limit
    arena.initialize();
    ArenaCounterObserver observer(arena, run);
    tls_run = run;
    arena.execute(work);
    peak = counter->peak.load();
  } catch (...) {
    tls_run = saved;
    release_counter(counter);
    throw;
  }
  tls_run = saved;
  release_counter(counter);
  return heap_meter_available() ? peak : -1;
}

}  // namespace grapebench

#ifdef GRAPEBENCH_HEAP_METER
// glibc's own entry points; the definitions below interpose the public names for the
// whole process (the executable's symbols come first in the dynamic link).
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);
void __libc_free(void*);
}

namespace {
inline void* counted(void* p) {
  if (!p) return p;
  if (grapebench::HeapCounter* c = grapebench::active_counter()) c->add(static_cast<std::int64_t>(malloc_usable_size(p)));
  return p;
}
inline void uncount(void* p) {
  if (!p) return;
  if (grapebench::HeapCounter* c = grapebench::active_counter()) c->add(-static_cast<std::int64_t>(malloc_usable_size(p)));
}
}  // namespace

extern "C" {
void* malloc(std::size_t n) { return counted(__libc_malloc(n)); }
void* calloc(std::size_t n, std::size_t size) { return counted(__libc_calloc(n, size)); }
void* realloc(void* p, std::size_t n) {
  uncount(p);
  void* q = __libc_realloc(p, n);
  if (!q && n != 0) return counted(p);  // failed: the old block is still held
  return counted(q);
}
void* memalign(std::size_t alignment, std::size_t n) { return counted(__libc_memalign(alignment, n)); }
void* aligned_alloc(std::size_t alignment, std::size_t n) { return counted(__libc_memalign(alignment, n)); }
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0) return EINVAL;
  void* p = __libc_memalign(alignment, n);
  if (!p) return ENOMEM;
  *out = counted(p);
  return 0;
}
void* valloc(std::size_t n) { return counted(__libc_valloc(n)); }
void* pvalloc(std::size_t n) { return counted(__libc_pvalloc(n)); }
void free(void* p) {
  uncount(p);
  __libc_free(p);
}
}
#endif
