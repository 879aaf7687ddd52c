// bench/heap_meter: every malloc-family allocation of a run is counted, on the
// calling thread and on the TBB workers that help it.
#include "bench/heap_meter.h"

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <cstdlib>
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

}  // namespace
}  // namespace grapebench
