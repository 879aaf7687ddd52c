// FNV-1a 64: the one hash of case keys, bootstrap seeds, the build identity and the
// Cycles render cache's keys.
// `h` continues a hash over several pieces (a file read in chunks).
#pragma once

#include <cstdint>
#include <string_view>

namespace grapebench {

// Not FNV's published offset basis (14695981039346656037): a digit short since the
// first case files. The start does not change how well it hashes; correcting it would
// change every case key (no cached case reused) and bootstrap seed (every interval),
// so it stays.
inline constexpr std::uint64_t kFnv1aOffset = 1469598103934665603ull;

inline std::uint64_t fnv1a(std::string_view s, std::uint64_t h = kFnv1aOffset) {
  for (unsigned char c : s) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace grapebench
