#include "sensors/render/huge_page_buffer.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <vector>

namespace grapebench {

namespace {

constexpr std::size_t kPage = std::size_t{1} << 21;
constexpr std::size_t kKeepBytes = std::size_t{256} << 20;

// Released buffers, by size; freed at exit.
struct Keep {
  std::mutex mutex;
  std::vector<std::pair<void*, std::size_t>> buffers;
  std::size_t bytes = 0;
  ~Keep() {
    for (const auto& b : buffers) std::free(b.first);
  }
};
Keep& keep() {
  static Keep k;
  return k;
}

}  // namespace

void FreeHugePages::operator()(void* p) const noexcept {
  if (p == nullptr) return;
  Keep& k = keep();
  {
    const std::lock_guard<std::mutex> lock(k.mutex);
    if (bytes > 0 && k.bytes + bytes <= kKeepBytes) {
      try {
        k.buffers.emplace_back(p, bytes);
        k.bytes += bytes;
        return;
      } catch (...) {  // no room to note it: freed below
      }
    }
  }
  std::free(p);
}

HugePageMemory huge_page_buffer(std::size_t bytes) {
  const std::size_t n = (std::max<std::size_t>(bytes, 1) + kPage - 1) / kPage * kPage;
  {
    Keep& k = keep();
    const std::lock_guard<std::mutex> lock(k.mutex);
    for (std::size_t i = k.buffers.size(); i-- > 0;) {
      if (k.buffers[i].second != n) continue;
      void* p = k.buffers[i].first;
      k.buffers.erase(k.buffers.begin() + static_cast<std::ptrdiff_t>(i));
      k.bytes -= n;
      return HugePageMemory(p, FreeHugePages{n});
    }
  }
  void* p = std::aligned_alloc(kPage, n);
  if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  (void)madvise(p, n, MADV_HUGEPAGE);  // advice only: refused, the pages are 4 KiB ones
#endif
  return HugePageMemory(p, FreeHugePages{n});
}

}  // namespace grapebench
