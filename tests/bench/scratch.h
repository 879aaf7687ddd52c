// Test helper: a fresh folder for a test's files (removed if it exists, not created),
// inside this process's own folder under the system's temporary folder. That folder is
// named after the pid, so two suites at once (CI beside a developer's run) never share
// a file, and it goes with everything in it when the process ends (synth's TempFolder;
// ctest runs each test in a process of its own). Fixed names under /tmp had left 3.9 GB
// behind on the development machine.
#pragma once

#include "synth/temp_folder.h"

#include <filesystem>
#include <string>

namespace grapebench {

inline std::filesystem::path scratch(const std::string& name) {
  static const TempFolder root("grapebench-tests");
  const std::filesystem::path d = root.path / name;
  std::filesystem::remove_all(d);
  return d;
}

}  // namespace grapebench
