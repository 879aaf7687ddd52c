// What every fuzz target shares: the input as text. A target calls the reader the
// harness uses; InputError (a clear message, exit 2) is an expected answer, anything
// else that escapes (a crash, a hang, a leak, another exception: exit 3) is a finding.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace grapebench {

inline std::string fuzz_text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

}  // namespace grapebench
