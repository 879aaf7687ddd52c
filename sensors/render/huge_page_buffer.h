// Large per-image buffers backed by 2 MiB pages where the kernel offers them
// (transparent huge pages in "madvise" mode, as on the CI machine). A fresh 42 MB
// buffer is then 21 page faults instead of 10,300: on the CI machine's virtualised
// kernel the ray-rendered pair took 283 against 539 ms (bunch) and 949 against
// 1231 ms (foliage) with and without (docs/sensors.md, "Speed"). Where the advice is
// refused the memory is ordinary. A released buffer is kept (up to 256 MiB in all)
// and handed to the next request of its size: its pages are already there, where a
// fresh one's are cleared by the kernel on first touch (docs/sensors.md, item 8).
#pragma once

#include <cstddef>
#include <memory>

namespace grapebench {

struct FreeHugePages {
  std::size_t bytes = 0;  // the buffer's rounded size: it goes back to the keep of that size
  void operator()(void* p) const noexcept;
};
using HugePageMemory = std::unique_ptr<void, FreeHugePages>;

// At least `bytes` of uninitialised memory (a kept buffer holds what its last owner
// wrote), 2 MiB aligned; throws std::bad_alloc.
HugePageMemory huge_page_buffer(std::size_t bytes);

}  // namespace grapebench
