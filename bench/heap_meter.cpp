#include "bench/heap_meter.h"

#include "synth/run_stop.h"

#include <dlfcn.h>
#include <malloc.h>

#include <algorithm>
#include <new>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <thread>
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
  std::int64_t limit = 0;             // bytes; 0: none
  std::atomic<bool> stop{false};      // the time budget passed: refuse every allocation
  std::atomic<bool> refused{false};   // an allocation passed the limit
  // True when an allocation of n bytes must fail.
  bool refuse(std::size_t n) {
    if (stop.load(std::memory_order_relaxed)) return true;
    if (limit > 0 && live.load(std::memory_order_relaxed) + static_cast<std::int64_t>(n) > limit) {
      refused.store(true, std::memory_order_relaxed);
      return true;
    }
    return false;
  }
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

#ifdef GRAPEBENCH_HEAP_METER
// The counter operator new charges (only with the replaced operators).
HeapCounter* active_counter() {
  HeapCounter* c = tls_run.counter;
  return c && c->generation.load(std::memory_order_relaxed) == tls_run.generation ? c : nullptr;
}
#endif

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
  c->limit = 0;
  c->stop = false;
  c->refused = false;
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
    if (!is_worker) return;
    tls_run = run_;
    tls_run_stop = &run_.counter->stop;
  }
  void on_scheduler_exit(bool is_worker) override {
    if (!is_worker) return;
    tls_run = ThreadRun{};
    tls_run_stop = nullptr;
  }

 private:
  ThreadRun run_;
};

}  // namespace

#ifdef GRAPEBENCH_HEAP_METER
// Compiled in, and in force: the process's malloc is the one below. Not so in Python's
// extension module (python/), which Python loads with RTLD_LOCAL, so the process keeps
// glibc's malloc and nothing would be counted: measured once, by a megabyte taken
// through the process's own malloc under a counter.
bool heap_meter_available() {
  static const bool in_force = [] {
    using Malloc = void* (*)(std::size_t);
    using Free = void (*)(void*);
    const auto process_malloc = reinterpret_cast<Malloc>(dlsym(RTLD_DEFAULT, "malloc"));
    const auto process_free = reinterpret_cast<Free>(dlsym(RTLD_DEFAULT, "free"));
    if (!process_malloc || !process_free) return false;
    HeapCounter* const counter = take_counter();
    const ThreadRun saved = tls_run;
    tls_run = ThreadRun{counter, counter->generation.load()};
    constexpr std::size_t kProbe = std::size_t{1} << 20;
    void* p = process_malloc(kProbe);
    const bool counted = counter->peak.load() >= static_cast<std::int64_t>(kProbe);
    process_free(p);
    tls_run = saved;
    release_counter(counter);
    return counted;
  }();
  return in_force;
}
#else
bool heap_meter_available() { return false; }
#endif

MeteredRun run_metered(const std::function<void()>& work, const RunBudget& budget) {
  HeapCounter* const counter = take_counter();
  counter->limit = budget.memory_mb > 0 ? static_cast<std::int64_t>(budget.memory_mb * 1e6) : 0;
  const ThreadRun run{counter, counter->generation.load()};
  const ThreadRun saved = tls_run;
  const std::atomic<bool>* const saved_stop = tls_run_stop;
  // The watchdog raises the stop flag at the deadline unless the work ends first.
  std::mutex mutex;
  std::condition_variable finished;
  bool done = false;
  std::thread watchdog;
  if (budget.seconds > 0) {
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                              std::chrono::duration<double>(budget.seconds));
    watchdog = std::thread([&, deadline] {
      std::unique_lock<std::mutex> lock(mutex);
      if (!finished.wait_until(lock, deadline, [&] { return done; })) counter->stop = true;
    });
  }
  const auto end_watch = [&] {
    if (!watchdog.joinable()) return;
    {
      const std::lock_guard<std::mutex> lock(mutex);
      done = true;
    }
    finished.notify_one();
    watchdog.join();
  };
  MeteredRun result;
  try {
    tbb::task_arena arena;  // the default concurrency, within the run's global limit
    arena.initialize();
    ArenaCounterObserver observer(arena, run);
    tls_run = run;
    tls_run_stop = &counter->stop;
    arena.execute(work);
    result.peak_bytes = counter->peak.load();
  } catch (...) {
    tls_run = saved;
    tls_run_stop = saved_stop;
    end_watch();
    release_counter(counter);
    throw;
  }
  tls_run = saved;
  tls_run_stop = saved_stop;
  end_watch();
  result.over_time = counter->stop.load();
  result.over_memory = counter->refused.load();
  release_counter(counter);
  if (!heap_meter_available()) result.peak_bytes = -1;
  return result;
}

std::int64_t peak_heap_bytes(const std::function<void()>& work) { return run_metered(work, RunBudget{}).peak_bytes; }

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

extern "C" int omp_get_level() __attribute__((weak));  // libgomp's, when loaded (PCL)

namespace {
// True when operator new must throw std::bad_alloc for the budget of this thread's
// run. Only C++ allocations are refused: C libraries (libsvm, qhull) do not check
// malloc's answer. Nor inside an OpenMP region (PCL's MLS, normals): an exception
// there terminates the program; the run is still marked over its budget.
inline bool new_refused(std::size_t n) {
  grapebench::HeapCounter* c = grapebench::active_counter();
  if (!c || !c->refuse(n)) return false;
  return !(omp_get_level && omp_get_level() > 0);  // any region, one thread or many
}
void* new_block(std::size_t n) {
  if (new_refused(n)) throw std::bad_alloc();
  for (;;) {
    if (void* p = std::malloc(n ? n : 1)) return p;
    const std::new_handler h = std::get_new_handler();
    if (!h) throw std::bad_alloc();
    h();
  }
}
void* new_aligned(std::size_t n, std::align_val_t a) {
  if (new_refused(n)) throw std::bad_alloc();
  const std::size_t align = std::max(static_cast<std::size_t>(a), sizeof(void*));
  for (;;) {
    void* p = nullptr;
    if (posix_memalign(&p, align, n ? n : 1) == 0) return p;
    const std::new_handler h = std::get_new_handler();
    if (!h) throw std::bad_alloc();
    h();
  }
}
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

// operator new, replaced to apply the run's budget (the blocks are malloc's: the
// library's operator delete frees them).
void* operator new(std::size_t n) { return new_block(n); }
void* operator new[](std::size_t n) { return new_block(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return new_block(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return new_block(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new(std::size_t n, std::align_val_t a) { return new_aligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return new_aligned(n, a); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return new_aligned(n, a);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return new_aligned(n, a);
  } catch (...) {
    return nullptr;
  }
}
#endif
