#include "bench/heap_meter.h"

#include <malloc.h>

#include <cstdlib>
#include <new>

namespace grapebench {
namespace heap_detail {
// Bytes this thread allocated minus bytes it freed, and the high-water mark.
thread_local std::int64_t current = 0;
thread_local std::int64_t peak = 0;
}  // namespace heap_detail

#ifdef GRAPEBENCH_HEAP_METER
bool heap_meter_available() { return true; }
#else
bool heap_meter_available() { return false; }
#endif

HeapMeter::HeapMeter() : base_(heap_detail::current) { heap_detail::peak = heap_detail::current; }

std::int64_t HeapMeter::peak_bytes() const { return heap_detail::peak - base_; }

}  // namespace grapebench

#ifdef GRAPEBENCH_HEAP_METER
namespace {
void* counted_alloc(std::size_t n) {
  void* p = std::malloc(n == 0 ? 1 : n);
  if (!p) throw std::bad_alloc();
  using namespace grapebench::heap_detail;
  current += static_cast<std::int64_t>(malloc_usable_size(p));
  if (current > peak) peak = current;
  return p;
}
void counted_free(void* p) noexcept {
  if (!p) return;
  grapebench::heap_detail::current -= static_cast<std::int64_t>(malloc_usable_size(p));
  std::free(p);
}
}  // namespace

void* operator new(std::size_t n) { return counted_alloc(n); }
void* operator new[](std::size_t n) { return counted_alloc(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_alloc(n);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { counted_free(p); }
void operator delete[](void* p) noexcept { counted_free(p); }
void operator delete(void* p, std::size_t) noexcept { counted_free(p); }
void operator delete[](void* p, std::size_t) noexcept { counted_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { counted_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { counted_free(p); }
#endif
