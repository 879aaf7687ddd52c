#include "sensors/render/huge_page_buffer.h"

#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <new>

namespace grapebench {

void FreeHugePages::operator()(void* p) const noexcept { std::free(p); }

HugePageMemory huge_page_buffer(std::size_t bytes) {
  constexpr std::size_t page = std::size_t{1} << 21;
  const std::size_t n = (std::max<std::size_t>(bytes, 1) + page - 1) / page * page;
  void* p = std::aligned_alloc(page, n);
  if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  (void)madvise(p, n, MADV_HUGEPAGE);  // advice only: refused, the pages are 4 KiB ones
#endif
  return HugePageMemory(p);
}

}  // namespace grapebench
