// sensors/render/huge_page_buffer.h: the memory is 2 MiB aligned, as large as asked,
// writable to its last byte (ASan would see an overrun), and freed by its owner; a
// released block serves the next request it fits, never one it would waste.
#include "sensors/render/huge_page_buffer.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>

namespace grapebench {
namespace {

TEST(HugePageBuffer, IsAlignedWritableAndAsLargeAsAsked) {
  for (const std::size_t bytes : {std::size_t{0}, std::size_t{1}, std::size_t{3} << 20, (std::size_t{42} << 20) + 17}) {
    const HugePageMemory m = huge_page_buffer(bytes);
    ASSERT_NE(m.get(), nullptr);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(m.get()) % (std::uintptr_t{1} << 21), 0u) << bytes;
    if (bytes == 0) continue;
    auto* p = static_cast<unsigned char*>(m.get());
    std::memset(p, 0xab, bytes);
    EXPECT_EQ(p[0], 0xab);
    EXPECT_EQ(p[bytes - 1], 0xab);
  }
}

TEST(HugePageBuffer, ReleasedBlockServesTheNextRequestItFits) {
  constexpr std::size_t MiB = std::size_t{1} << 20;
  void* first = nullptr;
  {
    const HugePageMemory m = huge_page_buffer(97 * MiB);
    first = m.get();
    EXPECT_EQ(m.get_deleter().bytes, 98 * MiB);
    std::memset(m.get(), 1, 97 * MiB);
  }
  // The released block is the newest kept one; 10 MiB would waste more than half of
  // it; 96 MiB fits it (no other test keeps one of 96-97 MiB).
  const HugePageMemory small = huge_page_buffer(10 * MiB);
  EXPECT_NE(small.get(), first);
  const HugePageMemory again = huge_page_buffer(96 * MiB);
  EXPECT_EQ(again.get(), first);
  EXPECT_EQ(again.get_deleter().bytes, 98 * MiB);
  std::memset(again.get(), 2, 98 * MiB);  // wholly usable again (ASan: unpoisoned)
}

}  // namespace
}  // namespace grapebench
