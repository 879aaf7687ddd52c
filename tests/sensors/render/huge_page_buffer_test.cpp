// sensors/render/huge_page_buffer.h: the memory is 2 MiB aligned, as large as asked,
// writable to its last byte (ASan would see an overrun), and freed by its owner, or
// kept for the next request of its size.
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

// A released buffer serves the next request of its size (its pages already there):
// the same memory, with what was written in it; another size gets other memory.
TEST(HugePageBuffer, AReleasedBufferServesTheNextRequestOfItsSize) {
  const std::size_t bytes = (std::size_t{6} << 20) + 5;
  void* first = nullptr;
  {
    const HugePageMemory m = huge_page_buffer(bytes);
    first = m.get();
    static_cast<unsigned char*>(m.get())[bytes - 1] = 0x5a;
  }
  const HugePageMemory again = huge_page_buffer(bytes - 3);  // the same 2 MiB pages
  EXPECT_EQ(again.get(), first);
  EXPECT_EQ(static_cast<unsigned char*>(again.get())[bytes - 1], 0x5a);
  const HugePageMemory other = huge_page_buffer(bytes + (std::size_t{2} << 20));
  EXPECT_NE(other.get(), first);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(other.get()) % (std::uintptr_t{1} << 21), 0u);
}

}  // namespace
}  // namespace grapebench
