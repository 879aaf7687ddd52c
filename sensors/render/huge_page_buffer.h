// Large per-image buffers backed by 2 MiB pages where the kernel offers them
// (transparent huge pages in "madvise" mode, as on the CI machine). A fresh 42 MB
// buffer is then 21 page faults instead of 10,300: on the CI machine's virtualised
// kernel the ray-rendered pair took 283 against 539 ms (bunch) and 949 against
// 1231 ms (foliage) with and without (docs/sensors.md, "Speed"). Where the advice is
// refused the memory is ordinary.
//
// A released buffer is kept for the next request it fits (a few, process-wide): glibc
// maps a buffer this large afresh each time, and the kernel then clears every page
// again, 5 % of a seed 001 run's CPU on the ray renderer (perf, docs/sensors.md
// "Speed"). The memory is uninitialised either way: its users write before they read.
#pragma once

#include <cstddef>
#include <memory>

namespace grapebench {

struct FreeHugePages {
  std::size_t bytes = 0;  // the block's size, a multiple of 2 MiB
  void operator()(void* p) const noexcept;
};
using HugePageMemory = std::unique_ptr<void, FreeHugePages>;

// At least `bytes` of uninitialised memory, 2 MiB aligned; throws std::bad_alloc.
HugePageMemory huge_page_buffer(std::size_t bytes);

}  // namespace grapebench
