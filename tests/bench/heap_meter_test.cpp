// bench/heap_meter: every malloc-family allocation of a run is counted, on the
// calling thread and on the TBB workers that help it.
#include "bench/heap_meter.h"
#include "synth/run_stop.h"

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdlib>
#include <new>
#include <vector>

namespace grapebench {
namespace {

// Keeps the compiler from eliding an allocation nothing reads.
void* escape(void* p) {
  asm volatile("" : : "r"(p) : "memory");
  return p;
}

TEST(HeapMeter, CountsAHundredMegabyteEigenMatrix) {
  if (!heap_meter_available()) GTEST_SKIP() << "sanitizer build: the counting malloc is not linked in";
  double sum = 0;
  const std::int64_t peak = peak_heap_bytes([&] {
    Eigen::MatrixXd m = Eigen::MatrixXd::Constant(3500, 3600, 1.0);  // 100.8 MB through Eigen's aligned malloc
    sum = m.sum();
  });
  EXPECT_EQ(sum, 3500.0 * 3600.0);
  EXPECT_GE(peak, 100'800'000);
  EXPECT_LT(peak, 101'500'000);
}

TEST(HeapMeter, CountsPlainMallocCallocReallocAndAlignedAlloc) {
  if (!heap_meter_available()) GTEST_SKIP();
  const std::int64_t peak = peak_heap_bytes([] {
    void* a = escape(std::malloc(10'000'000));
    void* b = escape(std::calloc(1'000'000, 10));
    void* c = escape(std::aligned_alloc(64, 10'000'000));
    a = escape(std::realloc(a, 20'000'000));
    std::free(a);
    std::free(b);
    std::free(c);
  });
  EXPECT_GE(peak, 40'000'000);
  EXPECT_LT(peak, 41'000'000);
  // Nothing held at the end, nothing counted after: a second run starts from zero.
  EXPECT_LT(peak_heap_bytes([] {}), 100'000);
}

TEST(HeapMeter, CountsWhatTbbWorkersAllocateForTheRun) {
  if (!heap_meter_available()) GTEST_SKIP();
  std::vector<void*> blocks(64);
  const std::int64_t peak = peak_heap_bytes([&] {
    // Every block stays alive until all are made: 64 MB whichever thread made each.
    tbb::parallel_for(0, 64, [&](int i) { blocks[static_cast<std::size_t>(i)] = escape(std::malloc(1'000'000)); });
    for (void* p : blocks) std::free(p);
  });
  EXPECT_GE(peak, 64'000'000);
  EXPECT_LT(peak, 65'000'000);
}

// Budgets (issue 23: no built-in estimator had a time limit; PB and the cylinder fit
// ran past 45 s on a camera inside a 1000-berry bunch).
double seconds_of(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(RunBudget, TheStopFlagEndsLoopsThatPollItOnEveryWorker) {
  MeteredRun m;
  bool stopped = false;
  const double s = seconds_of([&] {
    m = run_metered(
        [&] {
          try {
            tbb::parallel_for(0, 64, [](int) {
              for (;;) throw_if_stop_requested();
            });
          } catch (const std::exception&) {  // StopRequested, or bad_alloc if TBB's copy of it was refused
            stopped = true;
          }
        },
        RunBudget{0.2, 0});
  });
  EXPECT_TRUE(m.over_time);
  EXPECT_TRUE(stopped);
  EXPECT_LT(s, 5);
  EXPECT_EQ(tls_run_stop, nullptr);  // nothing left pointing at the finished run
}

TEST(RunBudget, AllocationsFailAfterTheDeadlineSoAllocatingLoopsEnd) {
  if (!heap_meter_available()) GTEST_SKIP() << "sanitizer build: the counting malloc is not linked in";
  MeteredRun m;
  bool failed = false;
  const double s = seconds_of([&] {
    m = run_metered(
        [&] {
          try {
            for (;;) escape(new std::vector<double>(1000));  // never polls
          } catch (const std::bad_alloc&) {
            failed = true;
          }
        },
        RunBudget{0.2, 0});
  });
  EXPECT_TRUE(m.over_time);
  EXPECT_TRUE(failed);
  EXPECT_LT(s, 5);
  void* after = std::malloc(1000);  // outside the run: allocations work again
  EXPECT_NE(after, nullptr);
  std::free(after);
}

TEST(RunBudget, TheMemoryBudgetRefusesTheAllocationThatPassesIt) {
  if (!heap_meter_available()) GTEST_SKIP() << "sanitizer build: the counting malloc is not linked in";
  bool refused = false;
  const MeteredRun m = run_metered(
      [&] {
        std::vector<char> small(8'000'000);  // within
        escape(small.data());
        try {
          std::vector<char> big(100'000'000);  // over 50 MB
          escape(big.data());
        } catch (const std::bad_alloc&) {
          refused = true;
        }
      },
      RunBudget{0, 50});
  EXPECT_TRUE(refused);
  EXPECT_TRUE(m.over_memory);
  EXPECT_FALSE(m.over_time);
  EXPECT_GT(m.peak_bytes, 8'000'000);
  EXPECT_LT(m.peak_bytes, 50'000'000);
}

}  // namespace
}  // namespace grapebench
