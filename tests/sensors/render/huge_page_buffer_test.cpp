// sensors/render/huge_page_buffer.h: the memory is 2 MiB aligned, as large as asked,
// writable to its last byte (ASan would see an overrun), and freed by its owner.
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

}  // namespace
}  // namespace grapebench
