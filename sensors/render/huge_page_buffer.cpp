#include "sensors/render/huge_page_buffer.h"

#include <sanitizer/asan_interface.h>  // no-op macros outside ASan
#include <sys/mman.h>

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <vector>

namespace grapebench {

namespace {

constexpr std::size_t kPage = std::size_t{1} << 21;
// At most this many blocks and bytes kept: two threads' buffers of a pair (the centre
// buffer and the sky filter's) with room to spare.
constexpr std::size_t kKeepBlocks = 8;
constexpr std::size_t kKeepBytes = std::size_t{512} << 20;

struct Block {
  void* p;
  std::size_t bytes;
};
struct Kept {
  std::mutex m;
  std::vector<Block> blocks;
  std::size_t bytes = 0;
};
// Never destroyed, so that a buffer released during exit still finds it; the blocks
// stay reachable from it (no leak to report).
Kept& kept() {
  static Kept* const k = [] {
    auto* n = new Kept;
    n->blocks.reserve(kKeepBlocks);
    return n;
  }();
  return *k;
}

}  // namespace

void FreeHugePages::operator()(void* p) const noexcept {
  if (p == nullptr) return;
  if (bytes > kKeepBytes) {
    std::free(p);
    return;
  }
  // Kept, the oldest kept ones freed to make room.
  Kept& k = kept();
  const std::lock_guard<std::mutex> lock(k.m);
  while (!k.blocks.empty() && (k.blocks.size() >= kKeepBlocks || k.bytes + bytes > kKeepBytes)) {
    ASAN_UNPOISON_MEMORY_REGION(k.blocks.front().p, k.blocks.front().bytes);
    std::free(k.blocks.front().p);
    k.bytes -= k.blocks.front().bytes;
    k.blocks.erase(k.blocks.begin());
  }
  k.blocks.push_back({p, bytes});  // the loop keeps size < kKeepBlocks, reserved: no allocation
  k.bytes += bytes;
  ASAN_POISON_MEMORY_REGION(p, bytes);  // a read after release is still caught
}

HugePageMemory huge_page_buffer(std::size_t bytes) {
  const std::size_t n = (std::max<std::size_t>(bytes, 1) + kPage - 1) / kPage * kPage;
  {
    // The smallest kept block that fits and wastes at most half of itself.
    Kept& k = kept();
    const std::lock_guard<std::mutex> lock(k.m);
    auto best = k.blocks.end();
    for (auto it = k.blocks.begin(); it != k.blocks.end(); ++it)
      if (it->bytes >= n && it->bytes <= 2 * n && (best == k.blocks.end() || it->bytes < best->bytes)) best = it;
    if (best != k.blocks.end()) {
      const Block b = *best;
      k.blocks.erase(best);
      k.bytes -= b.bytes;
      ASAN_UNPOISON_MEMORY_REGION(b.p, b.bytes);
      return HugePageMemory(b.p, FreeHugePages{b.bytes});
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
