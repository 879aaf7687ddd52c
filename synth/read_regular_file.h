// Reading a file named from outside (a scene, a baseline, a case file, a cloud) without
// blocking or swallowing whatever the name points at: a FIFO would block forever, a
// link to /dev/zero would read forever.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace grapebench {

// The bytes of the regular file at `path`. Throws InputError naming the path when it
// is missing, is not a regular file (saying what it is: a folder, a FIFO, a device,
// a socket), or holds more than `max_bytes` (the cap in the message).
std::string read_regular_file(const std::filesystem::path& path, std::size_t max_bytes);

}  // namespace grapebench
